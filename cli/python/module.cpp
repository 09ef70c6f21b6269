// cli/python/module.cpp — the module `fortu._fortu` (re-exported by the package `fortu`):
// compile(), Model, Field, Diagnostic, FortuError, and the docstrings users read.
#include "cli/python/arrays.hpp"
#include "cli/python/errors.hpp"
#include "cli/python/model_wrapper.hpp"
#include "cli/python/picture.hpp"

#include "cli/data_paths.hpp"
#include "interp/engine.hpp"
#include "interp/vm_import.hpp"

#include <pybind11/stl.h>

#include <fstream>
#include <sstream>

namespace py = pybind11;
using namespace fortu;
using namespace fortu::python;

namespace {

/// The keyword arguments left after the options: CONSTANT values (`R=0.8`), plus
/// `constants={...}` for names that clash with an option.
ConstantValues constants_of(const py::kwargs& kwargs, const py::object& constants) {
    ConstantValues values;
    auto add = [&](py::handle key, py::handle value) {
        const std::string name = py::str(key);
        if (!py::isinstance<py::float_>(value) && !py::isinstance<py::int_>(value))
            throw py::type_error("CONSTANT " + name + ": expected a number, got " +
                                 std::string(py::str(py::type::of(value).attr("__name__"))));
        values.emplace_back(name, value.cast<double>());
    };
    if (!constants.is_none())
        for (auto [key, value] : py::dict(constants)) add(key, value);
    for (auto [key, value] : kwargs) add(key, value);
    return values;
}

std::vector<py::handle> coordinates_of(py::handle x, py::handle y, py::handle z) {
    std::vector<py::handle> given{x};
    if (!y.is_none()) given.push_back(y);
    if (!z.is_none()) {
        if (y.is_none()) throw py::type_error("z given without y");
        given.push_back(z);
    }
    return given;
}

/// What compile() was given: a path (os.PathLike, or a str naming an existing file or ending
/// in .fortu/.vm without a newline) or the script's text.
std::pair<std::string, std::string> text_and_name(py::handle text_or_path) {
    const py::module_ os = py::module_::import("os");
    std::string path;
    if (py::isinstance(text_or_path, os.attr("PathLike"))) {
        path = py::str(os.attr("fspath")(text_or_path));
    } else if (py::isinstance<py::str>(text_or_path)) {
        const std::string s = text_or_path.cast<std::string>();
        const bool one_line = s.find('\n') == std::string::npos && s.find(';') == std::string::npos;
        auto ends_with = [&](const char* tail) {
            const std::string t = tail;
            if (s.size() < t.size()) return false;
            for (std::size_t i = 0; i < t.size(); ++i)
                if (std::tolower(static_cast<unsigned char>(s[s.size() - t.size() + i])) != t[i]) return false;
            return true;
        };
        if (one_line && (ends_with(".fortu") || ends_with(".vm") || os.attr("path").attr("isfile")(s).cast<bool>())) path = s;
        else return {s, "<string>"};
    } else {
        throw py::type_error("compile: expected the script's text or a path");
    }
    std::string error;
    const std::shared_ptr<SourceFile> source = SourceFile::load(path, error);
    if (!source) {
        PyErr_SetString(PyExc_FileNotFoundError, error.c_str());
        throw py::error_already_set();
    }
    return {source->text(), path};
}

std::vector<std::string> folders_of(py::handle include_path) {
    if (include_path.is_none()) return {};
    const py::module_ os = py::module_::import("os");
    if (py::isinstance<py::str>(include_path) || py::isinstance(include_path, os.attr("PathLike")))
        return {py::str(os.attr("fspath")(include_path))};
    std::vector<std::string> folders;
    for (py::handle folder : include_path) folders.push_back(py::str(os.attr("fspath")(folder)));
    return folders;
}

std::optional<std::string> rsystem_of(py::handle rsystem) {
    if (rsystem.is_none()) return std::nullopt;
    if (py::isinstance<py::float_>(rsystem) || py::isinstance<py::int_>(rsystem))
        return "alpha=" + std::string(py::str(py::repr(py::float_(py::reinterpret_borrow<py::object>(rsystem)))));
    return std::string(py::str(rsystem));
}

/// A view of the field's values whose base is the Field (no copy); float32 fields convert
/// once and keep the copy (the view is not kept: Field -> view -> Field would be a cycle
/// that reference counting never frees).
py::object field_values(py::object self) {
    FieldView& view = self.cast<FieldView&>();
    if (view.values) return view.values;
    const Grid& g = view.field.grid;
    std::vector<py::ssize_t> shape{g.rows(), g.cols()};
    if (g.dims == 3) shape.insert(shape.begin(), g.slices());
    py::array_t<double> values(shape, view.field.values.data(), self);
    if (!view.float32) return values;
    view.values = values.attr("astype")("float32");
    return view.values;
}

constexpr const char* kModuleDoc = R"(fortu: FORTU models (R-functions, the functional-voxel method) from Python.

    m = fortu.compile("examples/circles_or.fortu")      # or the script's text
    m.eval(0.1, 0.2)                                   # a float; arrays broadcast
    f = m.grid(size=800)                               # fortu.Field: f.values, f.x, f.y
    f.values.shape                                     # (800, 800), row 0 the largest Y
    m.grid(size=800, R=0.8)                            # a CONSTANT set for this call
    v, t, n = fortu.compile("examples/pawn.fortu").mesh(size=161)   # 3D models: a mesh

The values are the fortu command's, bit for bit (float64): m.eval(x, y) prints as
`fortu eval MODEL x y` does, m.grid(...).values equals `fortu run MODEL -o x.npy`,
m.mesh(...) is the mesh `fortu run MODEL -o m.ply` writes. Evaluation and meshing release
the GIL and stop on Ctrl-C (KeyboardInterrupt). A model or field shows as a picture in
Jupyter (_repr_png_).)";

constexpr const char* kGridDoc = R"(Samples the model on a grid, as `fortu run` does; returns a fortu.Field.

size: nodes per axis, both ends included: N, (W, H) or (W, H, D); default the script's
    RECTBMP, else 256x256 (2D) or 64x64x64 (3D).
domain: ((x0, x1), (y0, y1)[, (z0, z1)]) or (x0, x1, y0, y1[, z0, z1]); default the
    script's ARGUMENT ranges, else RECTANGLE, else [-1, 1].
precision: 'float64' (identical to every exact engine) or 'float32' (the voxel engine in
    single precision; Field.values is then float32).
engine: 'voxel' (default), 'classic', 'voxel-f32' or 'sign' (fortu.engines()).
threads: 0 for all cores.  max_points: larger grids raise ValueError (default 2**26).
budget: operations the classic engine may spend before the call is refused (ValueError).
constants / **R: CONSTANT values for this call (the script's first top-level CONSTANT of
    each name is replaced by the number); compiled once per set of values and kept.

The Field has .values, an ndarray in the command line's orientation: shape (rows, cols),
or (slices, rows, cols) in 3D; values[row, col] is the value at (x[col], y[row]) (and
values[slice, row, col] at z[slice]), where .x is ascending, .y DESCENDING (row 0 is the
largest Y, as in the picture) and .z ascending. np.asarray(field) gives the same values.)";

constexpr const char* kMeshDoc = R"(The model's zero surface as a closed triangle mesh: exactly the mesh
`fortu run MODEL --size ... --domain ... -o m.ply` writes. Returns (vertices, triangles, normals):
vertices float64 (n, 3); triangles uint32 (m, 3), indices into vertices (the PLY's own type),
counter-clockwise seen from outside; normals float64 (n, 3), the outward unit normal at each
vertex. Every edge is in exactly two triangles; a surface that misses the domain gives
empty (0, 3) arrays.

size, domain: the grid, as grid() takes them (its nodes are the lattice: N nodes, N - 1
cells per axis); at least 2 nodes per axis. Inside is value > 0; the domain's outer nodes
count as outside, so a solid the domain cuts is closed just inside its faces.
threads: 0 for all cores (the mesh is the same on any number).
max_points: grids of more nodes raise ValueError (default 2**28, the command line's limit;
    only the cells the surface crosses are kept).
constants / **R: CONSTANT values for this call, as grid() takes them.
ValueError for a 2D model. A UserWarning, the command line's note, where the mesh leaves out
a part of the solid thinner than a cell or puts a sharp edge more than half a cell off.)";

}  // namespace

PYBIND11_MODULE(_fortu, m) {
    m.doc() = kModuleDoc;
    register_errors(m);
    m.attr("DEFAULT_MAX_POINTS") = kDefaultMaxPoints;
    const py::object max_points = py::int_(kDefaultMaxPoints);

    py::class_<FieldView>(m, "Field", "A model sampled on a grid (see Model.grid): values, coordinates, picture.")
        .def_property_readonly("values", &field_values, "ndarray (rows, cols) or (slices, rows, cols); row 0 is the largest Y")
        .def_property_readonly("x", [](const FieldView& f) { return axis_coordinates(f.field.grid, 0); }, "column coordinates, ascending")
        .def_property_readonly("y", [](const FieldView& f) { return axis_coordinates(f.field.grid, 1); }, "row coordinates, descending")
        .def_property_readonly("z", [](const FieldView& f) -> py::object {
            if (f.field.grid.dims != 3) return py::none();
            return axis_coordinates(f.field.grid, 2);
        }, "slice coordinates, ascending (None in 2D)")
        .def_property_readonly("shape", [](py::object self) { return field_values(self).attr("shape"); })
        .def_property_readonly("domain", [](const FieldView& f) {
            const Grid& g = f.field.grid;
            py::list d;
            d.append(py::make_tuple(g.x.min, g.x.max));
            d.append(py::make_tuple(g.y.min, g.y.max));
            if (g.dims == 3) d.append(py::make_tuple(g.z.min, g.z.max));
            return py::tuple(d);
        })
        .def_readonly("engine", &FieldView::engine)
        .def_readonly("seconds", &FieldView::seconds, "evaluation time")
        .def("__array__", [](py::object self, py::object dtype) {
            py::object v = field_values(self);
            return dtype.is_none() ? v : v.attr("astype")(dtype);
        }, py::arg("dtype") = py::none())
        .def("_repr_png_", [](const FieldView& f) { return png_bytes(f.field); },
             "the picture `fortu run -o x.png` writes (3D: the middle slice)")
        .def("__repr__", [](py::object self) {
            const FieldView& f = self.cast<const FieldView&>();
            return "<fortu.Field " + std::string(py::str(self.attr("shape"))) + " " + f.engine + ">";
        });

    py::class_<ModelWrapper>(m, "Model", "A compiled FORTU model (see fortu.compile).")
        .def_property_readonly("arguments", [](const ModelWrapper& w) { return w.model().arguments; })
        .def_property_readonly("dims", [](const ModelWrapper& w) { return static_cast<int>(w.model().arguments.size()); })
        .def_property_readonly("path", [](const ModelWrapper& w) { return w.path(); })
        .def_property_readonly("source", [](const ModelWrapper& w) { return w.text(); })
        .def_property_readonly("diagnostics", &ModelWrapper::diagnostics, "warnings and notes of the compilation")
        .def("eval",
             [](ModelWrapper& w, py::handle x, py::handle y, py::handle z, int threads, std::size_t max_points,
                py::object constants, py::kwargs kwargs) {
                 return w.eval(coordinates_of(x, y, z), threads, max_points, constants_of(kwargs, constants));
             },
             py::arg("x"), py::arg("y") = py::none(), py::arg("z") = py::none(), py::kw_only(), py::arg("threads") = 0,
             py::arg("max_points") = max_points, py::arg("constants") = py::none(),
             R"(The model's value at points: numbers give a float, arrays (any shapes numpy
broadcasts) an ndarray of the broadcast shape. The same value `fortu eval` prints, bit for
bit. A 1-argument model takes x alone. CONSTANT values as keywords (R=0.8).
TypeError for a wrong count or dtype (complex, str, object), ValueError for shapes that do
not broadcast or more than max_points points.)")
        .def("gradient",
             [](ModelWrapper& w, py::handle x, py::handle y, py::handle z, std::size_t max_points,
                py::object constants, py::kwargs kwargs) {
                 return w.gradient(coordinates_of(x, y, z), max_points, constants_of(kwargs, constants));
             },
             py::arg("x"), py::arg("y") = py::none(), py::arg("z") = py::none(), py::kw_only(),
             py::arg("max_points") = max_points, py::arg("constants") = py::none(),
             "The exact gradient (dual numbers, as `fortu eval`): shape broadcast + (2,) or (3,); NaN where undefined.")
        .def("grid",
             [](ModelWrapper& w, py::handle size, py::handle domain, const std::string& precision, py::handle engine,
                int threads, std::size_t max_points, double budget, py::object constants, py::kwargs kwargs) {
                 return w.grid(size, domain, precision, engine, threads, max_points, budget, constants_of(kwargs, constants));
             },
             py::kw_only(), py::arg("size") = py::none(), py::arg("domain") = py::none(),
             py::arg("precision") = "float64", py::arg("engine") = py::none(), py::arg("threads") = 0,
             py::arg("max_points") = max_points, py::arg("budget") = 1e10, py::arg("constants") = py::none(), kGridDoc)
        .def("sign",
             [](ModelWrapper& w, py::handle size, py::handle domain, int threads, std::size_t max_points,
                py::object constants, py::kwargs kwargs) {
                 return w.grid(size, domain, "float64", py::str("sign"), threads, max_points, 1e10,
                               constants_of(kwargs, constants));
             },
             py::kw_only(), py::arg("size") = py::none(), py::arg("domain") = py::none(), py::arg("threads") = 0,
             py::arg("max_points") = max_points, py::arg("constants") = py::none(),
             "The sign (1, 0, -1, NaN) on a grid by the pruned renderer (`fortu run --sign-only`): a Field as grid() gives.")
        .def("mimages",
             [](ModelWrapper& w, py::handle size, py::handle domain, int threads, std::size_t max_points,
                py::object constants, py::kwargs kwargs) {
                 return w.mimages(size, domain, threads, max_points, constants_of(kwargs, constants));
             },
             py::kw_only(), py::arg("size") = py::none(), py::arg("domain") = py::none(), py::arg("threads") = 0,
             py::arg("max_points") = max_points, py::arg("constants") = py::none(),
             R"(The FV model's components n1..n4 (3D: n1..n5) of the float64 grid, unquantised (as
`--mimages m.exr`): shape (4, rows, cols) or (5, slices, rows, cols), same orientation as grid().)")
        .def("mesh",
             [](ModelWrapper& w, py::handle size, py::handle domain, int threads, std::size_t max_points,
                py::object constants, py::kwargs kwargs) {
                 return w.mesh(size, domain, threads, max_points, constants_of(kwargs, constants));
             },
             py::kw_only(), py::arg("size") = py::none(), py::arg("domain") = py::none(), py::arg("threads") = 0,
             py::arg("max_points") = kDefaultMeshMaxPoints, py::arg("constants") = py::none(), kMeshDoc)
        .def("singular_points",
             [](ModelWrapper& w, py::handle size, py::handle domain, py::object constants, py::kwargs kwargs) {
                 return w.singular_points(size, domain, constants_of(kwargs, constants));
             },
             py::kw_only(), py::arg("size") = py::none(), py::arg("domain") = py::none(), py::arg("constants") = py::none(),
             "The corners `fortu singular` finds (search grid: size, default 401 or 48 in 3D): ndarray (n, 2) or (n, 3).")
        .def("ir",
             [](ModelWrapper& w, const std::string& stage, py::object constants, py::kwargs kwargs) {
                 return w.ir(stage, constants_of(kwargs, constants));
             },
             py::arg("stage") = "lower", py::kw_only(), py::arg("constants") = py::none(),
             "What `fortu ir --stage STAGE` prints: 'lower' (the DAG), 'tape' or 'hoist'.")
        .def("_repr_png_", [](ModelWrapper& w) { return w.png({}); },
             "the picture `fortu run MODEL -o x.png` writes on the default grid")
        .def("__repr__", [](const ModelWrapper& w) {
            std::string args;
            for (const std::string& a : w.model().arguments) args += (args.empty() ? "" : ", ") + a;
            return "<fortu.Model " + w.path() + " (" + args + ")>";
        })
        .def(py::pickle(
            [](const ModelWrapper& w) {
                return py::make_tuple(w.text(), w.path(), w.include_path(), w.rsystem());
            },
            [](py::tuple t) {
                return ModelWrapper(t[0].cast<std::string>(), t[1].cast<std::string>(),
                                    t[2].cast<std::vector<std::string>>(), t[3].cast<std::optional<std::string>>());
            }));

    m.def("compile",
          [](py::handle text_or_path, py::handle include_path, py::handle rsystem) {
              auto [text, name] = text_and_name(text_or_path);
              return ModelWrapper(std::move(text), std::move(name), folders_of(include_path), rsystem_of(rsystem));
          },
          py::arg("text_or_path"), py::arg("include_path") = py::none(), py::arg("rsystem") = py::none(),
          R"(Compiles a model: a path (str naming a file or ending in .fortu/.vm, or os.PathLike)
or the script's text. include_path: folders INCLUDE searches after the script's own, before
the stdlib. rsystem: 'r0', 'minmax', 'alpha=0.5' or the alpha as a number (wins over the
script's RSYSTEM, as --rsystem does). Raises FortuError with the command line's diagnostics.)");
    m.def("engines", [] {
        std::vector<std::string> names;
        for (const Engine* e : engine_table()) names.emplace_back(e->name());
        return names;
    }, "The engines grid(engine=...) takes, as `fortu run --engine` lists them.");
    m.def("stdlib_path", [] { return stdlib_dirs(); }, "The folders INCLUDE searches last (the stdlib).");
}
