// cli/python/model_wrapper.cpp — compiling with CONSTANT values, the request checks, and each
// method as a call of the function the command line calls for the same thing.
#include "cli/python/model_wrapper.hpp"

#include "cli/data_paths.hpp"
#include "cli/mesh_notes.hpp"
#include "cli/model_setup.hpp"
#include "cli/option_table.hpp"
#include "cli/python/arrays.hpp"
#include "cli/python/errors.hpp"
#include "cli/python/interrupt.hpp"
#include "cli/python/picture.hpp"
#include "interp/grid_size.hpp"
#include "interp/mesher.hpp"
#include "interp/singular.hpp"
#include "interp/stage_print.hpp"
#include "interp/voxel_engine.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/resources.hpp"

#include <pybind11/stl.h>

#include <cmath>
#include <fmt/format.h>

namespace py = pybind11;

namespace fortu::python {
namespace {

/// Evaluations smaller than this run on the calling thread with the GIL held: a thread
/// and a signal watch would cost more than the work.
constexpr std::size_t kWatchedPoints = 4096;
/// Compiled CONSTANT variants kept per model.
constexpr std::size_t kKeptVariants = 8;

/// A real number (float, int, numpy scalar); TypeError otherwise.
double real_number(py::handle h) {
    if (py::isinstance<py::str>(h)) throw py::type_error("expected a number, got a str");
    const double v = PyFloat_AsDouble(h.ptr());
    if (v == -1.0 && PyErr_Occurred()) throw py::error_already_set();
    return v;
}

bool is_number(py::handle h) {
    return (py::isinstance<py::float_>(h) || py::isinstance<py::int_>(h)) && !py::isinstance<py::array>(h);
}

std::vector<int> size_of(py::handle size) {
    if (size.is_none()) return {};
    std::vector<int> nodes;
    auto add = [&](py::handle n) {
        if (!py::isinstance<py::int_>(n) && !py::isinstance<py::array>(n))
            throw py::type_error("size: expected an int or a sequence of 1 to 3 ints");
        const long v = n.cast<long>();
        if (v < 1 || v > 1'000'000) throw py::value_error(fmt::format("size: {} nodes is not between 1 and 1000000", v));
        nodes.push_back(static_cast<int>(v));
    };
    if (py::isinstance<py::sequence>(size) && !py::isinstance<py::str>(size)) {
        for (py::handle n : py::reinterpret_borrow<py::sequence>(size)) add(n);
        if (nodes.empty() || nodes.size() > 3) throw py::value_error("size: give 1 to 3 node counts");
    } else {
        add(size);
    }
    return nodes;
}

std::array<std::optional<AxisRange>, 3> domain_of(py::handle domain) {
    std::array<std::optional<AxisRange>, 3> ranges;
    if (domain.is_none()) return ranges;
    const char* usage = "domain: expected ((x0, x1), (y0, y1)[, (z0, z1)]) or (x0, x1, y0, y1[, z0, z1])";
    if (!py::isinstance<py::sequence>(domain) || py::isinstance<py::str>(domain)) throw py::type_error(usage);
    std::vector<double> ends;
    for (py::handle item : py::reinterpret_borrow<py::sequence>(domain)) {
        if (py::isinstance<py::sequence>(item) && !py::isinstance<py::str>(item)) {
            const auto pair = py::reinterpret_borrow<py::sequence>(item);
            if (pair.size() != 2) throw py::value_error(usage);
            for (py::handle end : pair) ends.push_back(real_number(end));
        } else {
            ends.push_back(real_number(item));
        }
    }
    if (ends.empty() || ends.size() % 2 || ends.size() > 6) throw py::value_error(usage);
    for (std::size_t a = 0; a * 2 < ends.size(); ++a) {
        const double lo = ends[2 * a], hi = ends[2 * a + 1];
        if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
            throw py::value_error(fmt::format("domain: axis {} needs finite min < max, got ({}, {})", "xyz"[a], lo, hi));
        ranges[a] = AxisRange{lo, hi};
    }
    return ranges;
}

const Engine& engine_of(py::handle engine, const std::string& precision, std::unique_ptr<Engine>& tuned) {
    EngineSettings settings;
    if (precision == "float32") settings.precision = Precision::Float32;
    else if (precision != "float64")
        throw py::value_error(fmt::format("precision: '{}' is neither 'float64' nor 'float32'", precision));
    const Engine* found = &default_engine();
    if (!engine.is_none()) {
        const std::string name = py::str(engine);
        found = find_engine(name);
        if (!found) throw py::value_error(fmt::format("engine: unknown engine '{}' (known: {})", name, engine_names(", ", " or ")));
    }
    tuned = found->tuned(settings);
    return *tuned;
}

void check_points(std::size_t points, std::size_t max_points, bool arrays) {
    if (points <= max_points) return;
    if (!arrays)   // a mesh allocates only what its surface crosses: the limit is on its time
        throw py::value_error(fmt::format("{} grid nodes requested, more than max_points = {}; raise max_points "
                                          "if the time is there",
                                          points, max_points));
    throw py::value_error(fmt::format("{} points requested, more than max_points = {} (each float64 array "
                                      "{}); evaluate in pieces, or raise max_points if the memory is there",
                                      points, max_points, format_bytes(max_points * sizeof(double))));
}

}  // namespace

ModelWrapper::ModelWrapper(std::string text, std::string path, std::vector<std::string> include_path,
                           std::optional<std::string> rsystem)
    : source_(std::make_shared<SourceFile>(std::move(path), std::move(text))),
      include_path_(std::move(include_path)),
      rsystem_text_(std::move(rsystem)) {
    if (rsystem_text_) {
        rsystem_ = parse_rsystem(*rsystem_text_);
        if (!rsystem_)
            throw py::value_error(fmt::format("rsystem: '{}' is not r0, minmax, r1 or alpha=A with A in (-1, 1]",
                                              *rsystem_text_));
    }
    compiled_ = compile_with({}, &warnings_);
}

std::shared_ptr<const ModelWrapper::Compiled> ModelWrapper::compile_with(const ConstantValues& constants,
                                                                   std::vector<DiagnosticView>* warnings) const {
    DiagnosticSink sink;
    CompileOptions options;
    options.rsystem = rsystem_;
    options.include_dirs = include_path_;
    for (const std::string& dir : stdlib_dirs()) options.include_dirs.push_back(dir);
    options.constants = constants;
    std::optional<Model> model = compile_model(source_, options, sink);
    if (!model) raise_fortu_error(sink.diagnostics());
    if (warnings) *warnings = diagnostic_views(sink.diagnostics());
    PointListEvaluator points(model->graph, model->root);
    return std::make_shared<const Compiled>(Compiled{constants, std::move(*model), std::move(points)});
}

std::shared_ptr<const ModelWrapper::Compiled> ModelWrapper::with(const ConstantValues& constants) {
    if (constants.empty()) return compiled_;
    for (auto it = variants_.begin(); it != variants_.end(); ++it) {
        if ((*it)->constants != constants) continue;
        variants_.splice(variants_.begin(), variants_, it);
        return variants_.front();
    }
    variants_.push_front(compile_with(constants, nullptr));
    if (variants_.size() > kKeptVariants) variants_.pop_back();
    return variants_.front();
}

py::list ModelWrapper::diagnostics() const { return py::cast(warnings_); }

Grid ModelWrapper::grid_for(const Model& model, py::handle size, py::handle domain, std::size_t max_points,
                            bool arrays) const {
    const std::vector<int> nodes = size_of(size);
    if (model.dims() == 2 && nodes.size() == 3)
        throw py::value_error(fmt::format("size: the model has {} argument(s); give N or (W, H)", model.arguments.size()));
    const Grid grid = sized_grid(model, nodes, domain_of(domain));  // the CLI's --size: square cells
    check_points(grid.points(), max_points, arrays);
    return grid;
}

namespace {

/// The number of coordinate arrays given; a TypeError unless the model takes that many.
int coordinate_count(int dims, const std::vector<py::handle>& coordinates) {
    const int given = static_cast<int>(coordinates.size());
    if (given != std::max(dims, 2) && !(dims == 1 && given == 1))
        throw py::type_error(fmt::format("the model has {} argument(s); give {} coordinate(s)", dims, std::max(dims, 2)));
    return given;
}

}  // namespace

py::object ModelWrapper::eval(const std::vector<py::handle>& coordinates, int threads, std::size_t max_points,
                              const ConstantValues& constants) {
    const std::shared_ptr<const Compiled> held = with(constants);
    const Compiled& c = *held;
    const int dims = static_cast<int>(c.model.arguments.size());
    const int given = coordinate_count(dims, coordinates);
    bool scalars = true;
    for (py::handle h : coordinates) scalars = scalars && is_number(h);
    if (scalars) {
        std::array<double, 3> p{0, 0, 0};
        for (int i = 0; i < given; ++i) p[i] = coordinates[i].cast<double>();
        return py::float_(c.points.value(p));
    }
    const PointArrays arrays(coordinates);
    check_points(arrays.points(), max_points, /*arrays=*/true);
    std::vector<double> out(arrays.points());
    EvalOptions options;
    options.threads = threads;
    auto work = [&](const std::atomic<bool>* cancel) {
        options.cancel = cancel;
        c.points.values(arrays.points(), [&](std::size_t first, int count, double* x, double* y, double* z) {
            double* const axes[3] = {x, y, z};
            arrays.gather(first, count, axes);
        }, out.data(), options);
    };
    if (arrays.points() < kWatchedPoints) work(nullptr);
    else run_interruptible(work);
    return owning_array(std::move(out), arrays.shape());
}

py::array ModelWrapper::gradient(const std::vector<py::handle>& coordinates, std::size_t max_points,
                                 const ConstantValues& constants) {
    const std::shared_ptr<const Compiled> held = with(constants);
    const Compiled& c = *held;
    const int dims = static_cast<int>(c.model.arguments.size());
    const int given = coordinate_count(dims, coordinates);
    const PointArrays arrays(coordinates);
    check_points(arrays.points() * std::max(dims, 2), max_points, /*arrays=*/true);
    const int components = std::max(dims, 2);
    std::vector<double> out(arrays.points() * components);
    auto work = [&](const std::atomic<bool>* cancel) {
        const PointEvaluator evaluate(c.model.graph, c.model.root);   // value and exact gradient, as `fortu eval`
        std::array<double, kTileSize> axis[3];
        for (std::size_t first = 0; first < arrays.points(); first += kTileSize) {
            if (cancel && cancel->load()) return;
            const int count = static_cast<int>(std::min<std::size_t>(kTileSize, arrays.points() - first));
            double* const axes[3] = {axis[0].data(), axis[1].data(), axis[2].data()};
            arrays.gather(first, count, axes);
            for (int i = 0; i < count; ++i) {
                const PointValue v = evaluate({axis[0][i], given > 1 ? axis[1][i] : 0.0, given > 2 ? axis[2][i] : 0.0});
                for (int k = 0; k < components; ++k) out[(first + i) * components + k] = v.gradient[k];
            }
        }
    };
    if (arrays.points() < kWatchedPoints) work(nullptr);
    else run_interruptible(work);
    std::vector<py::ssize_t> shape = arrays.shape();
    shape.push_back(components);
    return owning_array(std::move(out), shape);
}

FieldView ModelWrapper::grid(py::handle size, py::handle domain, const std::string& precision, py::handle engine,
                             int threads, std::size_t max_points, double budget, const ConstantValues& constants) {
    const std::shared_ptr<const Compiled> held = with(constants);
    const Compiled& c = *held;
    std::unique_ptr<Engine> tuned;
    const Engine& chosen = engine_of(engine, precision, tuned);
    const Grid grid = grid_for(c.model, size, domain, max_points);
    if (const std::optional<std::string> refusal = classic_refusal(c.model, chosen, double(grid.points()), budget))
        throw py::value_error(*refusal);
    FieldView view;
    view.float32 = chosen.capabilities().float32;
    view.engine = std::string(chosen.name());
    EvalOptions options;
    options.threads = threads;
    run_interruptible([&](const std::atomic<bool>* cancel) {
        options.cancel = cancel;
        Stopwatch clock;
        view.field = evaluate_grid(c.model, grid, chosen, options);
        view.seconds = clock.seconds();
    });
    return view;
}

py::array ModelWrapper::mimages(py::handle size, py::handle domain, int threads, std::size_t max_points,
                                const ConstantValues& constants) {
    const std::shared_ptr<const Compiled> held = with(constants);
    const Compiled& c = *held;
    const Grid grid = grid_for(c.model, size, domain, max_points);
    const int components = grid.dims == 3 ? 5 : 4;
    std::vector<double> out;
    EvalOptions options;
    options.threads = threads;
    run_interruptible([&](const std::atomic<bool>* cancel) {
        options.cancel = cancel;
        const Field field = evaluate_grid(c.model, grid, default_engine(), options);
        if (cancel->load()) return;
        const FvModel fv(field);
        out.reserve(grid.points() * components);
        for (int k = 1; k <= components; ++k) {
            const std::span<const double> image = fv.image(k);
            out.insert(out.end(), image.begin(), image.end());
        }
    });
    std::vector<py::ssize_t> shape{components, grid.rows(), grid.cols()};
    if (grid.dims == 3) shape.insert(shape.begin() + 1, grid.slices());
    return owning_array(std::move(out), shape);
}

py::tuple ModelWrapper::mesh(py::handle size, py::handle domain, int threads, std::size_t max_points,
                             const ConstantValues& constants) {
    const std::shared_ptr<const Compiled> held = with(constants);
    const Compiled& c = *held;
    const Grid grid = grid_for(c.model, size, domain, max_points, /*arrays=*/false);
    if (const std::optional<MeshRefusal> refusal = mesh_refusal(c.model, grid))
        throw py::value_error(refusal->size_at_fault ? "size: " + refusal->message : refusal->message);
    Mesh mesh;
    MeshStats stats;
    EvalOptions options;
    options.threads = threads;
    run_interruptible([&](const std::atomic<bool>* cancel) {
        options.cancel = cancel;
        mesh = extract_mesh(c.model.graph, c.model.root, grid, options, &stats);
    });
    // What the mesh leaves out, as the command line's notes: warnings, which a caller may
    // turn into errors or silence.
    for (const std::string& note : mesh_notes(stats, grid))
        if (PyErr_WarnEx(PyExc_UserWarning, note.c_str(), 1) < 0) throw py::error_already_set();
    return py::make_tuple(owning_rows(std::move(mesh.vertices)), owning_rows(std::move(mesh.triangles)),
                          owning_rows(std::move(mesh.normals)));
}

py::array ModelWrapper::singular_points(py::handle size, py::handle domain, const ConstantValues& constants) {
    const std::shared_ptr<const Compiled> held = with(constants);
    const Compiled& c = *held;
    const int dims = c.model.dims();
    const Grid grid = grid_for(c.model, size.is_none() ? py::int_(dims == 3 ? 48 : 401) : size, domain, kDefaultMaxPoints);
    SingularSet found;
    run_interruptible([&](const std::atomic<bool>*) { found = find_singular_set(c.model, grid); });
    std::vector<double> out;
    for (const SingularPoint& s : found.points) out.insert(out.end(), s.point.begin(), s.point.begin() + dims);
    return owning_array(std::move(out), {static_cast<py::ssize_t>(found.points.size()), dims});
}

std::string ModelWrapper::ir(const std::string& stage, const ConstantValues& constants) {
    const std::optional<IrStage> parsed = parse_ir_stage(stage);
    if (!parsed) throw py::value_error(fmt::format("stage: '{}' is not lower, tape or hoist", stage));
    return print_stage(with(constants)->model, path(), *parsed);
}

py::bytes ModelWrapper::png(const ConstantValues& constants) {
    FieldView view = grid(py::none(), py::none(), "float64", py::none(), 0, kDefaultMaxPoints, 1e10, constants);
    return png_bytes(view.field);
}

}  // namespace fortu::python
