// cli/main.cpp — the `fortu` binary: run, eval, check, ir, singular here, golden, bench and
// repl handed to their libraries (commands.hpp). Each command here loads and
// compiles the model through interp/, then evaluates and writes through the engines and
// runtime/ writers. Exit status: 0 success, 1 model error, 2 usage error.
#include "cli/brick_run.hpp"
#include "cli/cli_options.hpp"
#include "cli/commands.hpp"
#include "cli/compare_report.hpp"
#include "cli/data_paths.hpp"
#include "cli/fv_steps.hpp"
#include "cli/mesh_output.hpp"
#include "cli/model_setup.hpp"
#include "cli/mpi_world.hpp"
#include "cli/point_report.hpp"
#include "cli/run_checks.hpp"
#include "cli/picture_options.hpp"
#include "cli/run_feedback.hpp"
#include "cli/run_grid.hpp"
#include "cli/standard_streams.hpp"
#include "cli/sweep.hpp"

#include "grammar/diagnostic.hpp"
#include "interp/classic_cost.hpp"
#include "interp/engine.hpp"
#include "interp/ir_print.hpp"
#include "interp/lower.hpp"
#include "interp/sign_render.hpp"
#include "interp/tape_jit.hpp"
#include "interp/singular.hpp"
#include "interp/vector_math.hpp"
#include "interp/voxel_engine.hpp"
#include "interp/vm_import.hpp"
#include "runtime/field_stats.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/progress.hpp"
#include "runtime/resources.hpp"

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <limits>
#include <malloc.h>
#include <unistd.h>

namespace fortu {
namespace {

/// glibc's defaults give memory back to the system as soon as 128 KiB is free at the heap's
/// top, and put every block over 128 KiB in a mapping of its own, unmapped when freed: a run
/// that allocates and frees scratch as it goes pays system calls and zero-filled page faults
/// for the same memory again. Blocks up to 32 MiB from the heap, kept when freed up to
/// 64 MiB, the heap grown 8 MiB at a time: prospero.vm's 1024² sign image in a fresh process
/// 7.7 → 7.0 ms (medians of 15; 1,678 → 1,387 page faults; its second run in one process
/// takes 6.3 ms). Only the command line does this: the Python module lives in someone
/// else's process.
void tune_allocator() {
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    mallopt(M_TOP_PAD, 8 << 20);
}

constexpr int kExitModelError = 1;
constexpr int kExitUsage = 2;

/// Reads and compiles `path` (MODEL, or "-" for standard input); prints its diagnostics
/// (notes only when asked).
std::optional<Model> load_model(const CliOptions& o, const std::string& path, bool show_notes, double& seconds) {
    Stopwatch clock;
    std::string error;
    auto source = load_script_argument(path, error);
    if (!source) {
        std::cerr << fmt::format("fortu: error: {}\n", error);
        return std::nullopt;
    }
    DiagnosticSink sink;
    CompileOptions options;
    options.rsystem = o.rsystem;
    options.include_dirs = include_search_path(o.include_dirs);
    options.limits = o.limits;
    options.constants = o.constants;
    std::optional<Model> model = compile_model(source, options, sink);
    for (const Diagnostic& d : sink.diagnostics())
        if (d.severity != Severity::Note || show_notes) std::cerr << render(d);
    seconds = clock.seconds();
    return model;
}

std::optional<Model> load_model(const CliOptions& o, bool show_notes, double& seconds) {
    return load_model(o, o.positional[0], show_notes, seconds);
}

Grid make_grid(const Model& model, const CliOptions& o) { return run_grid(model, o); }

/// `fortu check A B ...`: each file in turn; the exit status is the worst.
int command_check(const CliOptions& o) {
    int status = 0;
    for (const std::string& path : o.positional) {
        double seconds = 0;
        std::optional<Model> model = load_model(o, path, /*show_notes=*/true, seconds);
        if (!model) {
            status = kExitModelError;
            continue;
        }
        std::cout << fmt::format("{}: ok ({} argument{}, {} nodes)\n", shown_script_name(path),
                                 model->arguments.size(), model->arguments.size() == 1 ? "" : "s",
                                 ir_stats(*model).nodes);
    }
    return status;
}

int command_ir(const CliOptions& o) {
    double seconds = 0;
    std::optional<Model> model = load_model(o, false, seconds);
    if (!model) return kExitModelError;
    std::cout << print_stage(*model, shown_script_name(o.positional[0]), o.stage);
    return 0;
}

double parse_coordinate(const std::string& text) {
    try {
        std::size_t used = 0;
        double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v)) return v;
    } catch (...) {
    }
    throw UsageError(fmt::format("'fortu eval': '{}' is not a finite coordinate", text));
}

/// Refuses a classic run whose expanded-tree cost exceeds the budget (unless --force).
bool classic_within_budget(const Model& model, const CliOptions& o, double points) {
    // --force lifts the operation budget, never the depth bound (deeper recursion overflows the stack).
    const double budget = o.force ? std::numeric_limits<double>::infinity() : o.budget;
    const std::optional<std::string> refusal = classic_refusal(model, *o.engine, points, budget);
    if (refusal) std::cerr << fmt::format("fortu: error: {}\n", *refusal);
    return !refusal;
}

int command_eval(const CliOptions& o) {
    double seconds = 0;
    std::optional<Model> model = load_model(o, false, seconds);
    if (!model) return kExitModelError;
    std::array<double, 3> p{0, 0, 0};
    const int given = static_cast<int>(o.positional.size()) - 1;
    const int dims = static_cast<int>(model->arguments.size());
    if (given != std::max(dims, 2) && !(dims == 1 && given == 1))
        throw UsageError(fmt::format("'fortu eval': the model has {} argument(s); give {} coordinate(s)",
                                     dims, std::max(dims, 2)));
    for (int i = 0; i < given; ++i) p[i] = parse_coordinate(o.positional[1 + i]);
    if (!o.engine->capabilities().point)
        throw UsageError(fmt::format("'fortu eval': the {} engine evaluates whole grids only (use {})", o.engine->name(),
                                     engine_names(", ", " or ", [](const EngineCapabilities& c) { return c.point; })));
    if (!classic_within_budget(*model, o, 1.0 + model->dims())) return kExitUsage;

    const std::unique_ptr<Engine> engine = o.engine->tuned(o.engine_settings);
    std::cout << point_report(*model, p, *engine, make_grid(*model, o));
    return 0;
}

int command_singular(const CliOptions& o) {
    double seconds = 0;
    std::optional<Model> model = load_model(o, false, seconds);
    if (!model) return kExitModelError;
    if (o.slice && model->dims() != 3)
        throw UsageError("--slice: the model has 2 arguments; slices are planes of 3D models");
    CliOptions search = o;
    if (search.size.empty()) search.size = {model->dims() == 3 ? 48 : 401};
    search.slice.reset();   // the search covers the cube; --slice picks the picture's slice
    const Grid grid = make_grid(*model, search);
    if (!o.output.empty()) check_outputs(o, grid);   // before the search, not after it
    const SingularSet singular = find_singular_set(*model, grid);
    const std::vector<SingularPoint>& points = singular.points;
    std::cout << fmt::format("{}: {} singular point{} (K = 0 and R = 0) in x [{}, {}], y [{}, {}]{}\n",
                             shown_script_name(o.positional[0]), points.size(), points.size() == 1 ? "" : "s",
                             grid.x.min,
                             grid.x.max, grid.y.min, grid.y.max,
                             grid.dims == 3 ? fmt::format(", z [{}, {}]", grid.z.min, grid.z.max) : "");
    for (const SingularPoint& s : points) {
        if (grid.dims == 3) std::cout << fmt::format("({}, {}, {})", s.point[0], s.point[1], s.point[2]);
        else std::cout << fmt::format("({}, {})", s.point[0], s.point[1]);
        std::cout << fmt::format("  corner of {} R-operation{}\n", s.operations, s.operations == 1 ? "" : "s");
    }
    for (const SingularCurve& c : singular.curves)
        std::cout << fmt::format("curve through ({}, {}): the singular set is a curve there (an R-operation's "
                                 "operands vanish together along it, {} search cells; K = 0 and R = 0 all along)\n",
                                 c.point[0], c.point[1], c.cells);
    if (!o.output.empty()) {
        OutputOptions out;
        out.picture = o.picture;
        if (o.slice && grid.dims == 3) out.slice = z_slice_number(grid, *o.slice);
        const Field field = evaluate_grid(*model, grid, default_engine());
        const int slice = grid.dims == 3 ? (o.slice ? out.slice : grid.slices() / 2) : 0;
        for (const SingularPoint& s : points)
            if (grid.dims == 2 || std::fabs(s.point[2] - grid.z_at(slice)) <= grid.z.step() / 2)
                out.markers.push_back({s.point[0], s.point[1]});
        try {
            write_field(field, o.output, out);
        } catch (const OutputError& e) {
            std::cerr << fmt::format("fortu: error: {}\n", e.what());
            return kExitModelError;
        }
    }
    return 0;
}

/// `fortu run` of a 3D model to a picture without --slice: the shaded view of the solid.
int run_shaded_view(const Model& model, const CliOptions& o) {
    const std::array<AxisRange, 3> box = run_box(model, o);
    const std::array<int, 2> size = view_size(o);
    if (double(size[0]) * size[1] > double(kMaxGridPoints))
        throw UsageError(fmt::format("--size: a {}x{} picture is more than fortu allocates", size[0], size[1]));
    EvalOptions eval;
    eval.threads = o.threads;
    Stopwatch clock;
    ShadedViewStats view_stats;
    const SurfaceImage image = render_shaded_view(model.graph, model.root, box, o.view, size[0], size[1], eval,
                                                  o.engine_settings.compile, &view_stats);
    const double seconds = clock.seconds();
    try {
        write_surface_picture(image, o.output);
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return kExitModelError;
    }
    std::cerr << written_picture_line(o, o.output, size[0], size[1]);
    if (o.stats)
        report_stream(o) << fmt::format(
            "model: {}\nshaded view: {}x{}, azimuth {}, elevation {}, x [{}, {}], y [{}, {}], "
            "z [{}, {}]\nleaves: {}, {} of them on compiled tapes ({} tapes compiled)\ntime: render {:.3f} s\n"
            "peak memory: {}\n",
            shown_script_name(o.positional[0]), size[0], size[1], o.view.azimuth, o.view.elevation, box[0].min,
            box[0].max, box[1].min, box[1].max, box[2].min, box[2].max, format_count(view_stats.leaves),
            format_count(view_stats.compiled_leaves), view_stats.tapes_compiled, seconds, format_bytes(peak_rss_bytes()));
    return 0;
}

int command_run_files(const CliOptions& o);

/// `fortu run`: `-o -` writes into a temporary file sent to standard output once complete.
int command_run(const CliOptions& o) {
    if (!o.sets.empty()) {
        World& world = World::get();
        if (!world.distributed()) return run_sweep(o, command_run);
        World::Counter counter(world);   // the points are shared out like bricks (one at a time)
        return run_sweep(o, command_run, [&counter] { return counter.next(); });
    }
    if (!is_stdout_path(o.output)) return command_run_files(o);
    StdoutOutput out(o.format);
    CliOptions to_file = o;
    to_file.output = out.path();
    const int status = command_run_files(to_file);
    if (status == 0) out.send();
    return status;
}

int command_run_files(const CliOptions& o) {
    double compile_seconds = 0;
    std::optional<Model> model = load_model(o, false, compile_seconds);
    if (!model) return kExitModelError;
    if (wants_shaded_view(*model, o)) {
        if (o.picture.legend || o.picture.level_count > 0 || !o.picture.levels.empty() ||
            o.picture.scale.mode != ScaleChoice::Mode::Auto)
            throw UsageError("--legend, --levels and --scale colour a plane by its values; a 3D picture without "
                             "--slice is a shaded view of the solid (add --slice z=V)");
        // The view needs no grid; --mimages and --contour still draw the cube's middle slice.
        CliOptions rest = o;
        rest.output.clear();
        const bool slices_too = !o.mimages.empty() || !o.contour.empty();
        if (slices_too) check_outputs(o, make_grid(*model, rest));   // before anything is written
        const int status = run_shaded_view(*model, o);
        if (status != 0 || !slices_too) return status;
        return command_run_files(rest);
    }
    if (wants_bricks(*model, o)) return run_bricked(*model, o, compile_seconds);
    if (World::get().distributed() && World::get().rank() != 0 && !o.sweep_point) return 0;   // only bricks and sweeps are shared
    const Grid grid = make_grid(*model, o);
    check_outputs(o, grid);
    if (is_mesh_output(o.output)) return run_mesh_output(*model, grid, o, compile_seconds);
    check_memory(o, grid);
    if (!classic_within_budget(*model, o, double(grid.points()))) return kExitUsage;
    CliOptions reference_options = o;
    if (o.compare) reference_options.engine = o.compare;
    if (o.compare && !classic_within_budget(*model, reference_options, double(grid.points()))) return kExitUsage;

    const std::unique_ptr<Engine> engine = o.engine->tuned(o.engine_settings);
    const EngineCapabilities can = engine->capabilities();
    Progress progress(fmt::format("{} {}", engine->name(), grid_text(grid)), grid.points());
    EvalOptions eval;
    eval.threads = o.threads;
    eval.progress = [&](std::size_t n) { progress.advance(n); };
    std::optional<StepWriter> steps;
    if (!o.steps.empty()) {
        eval.steps = model->definitions;
        eval.steps.emplace_back("RETURN", model->root);
        // With --slice the grid is already that one plane.
        steps.emplace(o.steps, eval.steps.size(), OutputOptions{});
        eval.on_step = [&steps](const EvalStep& step) { (*steps)(step); };
    }
    Stopwatch clock;
    // Signs stay int8 (SignVolume); float64 only if a file or a comparison needs values.
    std::optional<SignVolume> signs;
    Field field;
    if (eval.steps.empty() && dynamic_cast<const SignEngine*>(engine.get()))
        signs = sign_render_volume(model->graph, model->root, grid, eval);
    else
        field = evaluate_grid(*model, grid, *engine, eval);
    const double eval_seconds = clock.seconds();
    const std::size_t eval_peak = peak_rss_bytes();  // before any image writer loads OpenImageIO
    progress.finish();

    const FieldStats stats = signs ? signs->stats() : field_stats(field);
    if (signs && (!o.output.empty() || !o.mimages.empty() || !o.contour.empty() || o.compare))
        field = signs->expanded();
    if (stats.invalid > 0)
        std::cerr << fmt::format("fortu: note: {} invalid point{} (non-finite values)\n", stats.invalid,
                                 stats.invalid == 1 ? "" : "s");
    Stopwatch write_clock;
    OutputOptions out;
    out.npy_float32 = o.float32;
    out.vdb_band = o.vdb_band;
    out.npy_sidecar = true;
    out.picture = plane_picture_style(field, o.picture);
    try {
        // Pictures of an x or y plane show it with Z up; values files keep the grid's axes.
        const bool picture = !o.output.empty() && output_format_for(o.output)->kind != OutputKind::Field;
        if (!o.output.empty()) write_field(picture ? plane_picture(field) : field, o.output, out);
        if (!o.mimages.empty()) write_mimages(plane_picture(field), o.mimages, out);
        if (!o.contour.empty()) write_field(plane_picture(field), o.contour, out);
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return kExitModelError;
    }
    const double write_seconds = write_clock.seconds();
    std::cerr << written_lines(o, grid);
    if (steps) std::cerr << written_steps_line(o, grid, steps->files());
    std::ostream& report = report_stream(o);
    if (o.compare) {
        const std::unique_ptr<Engine> reference = o.compare->tuned(o.engine_settings);
        EvalOptions quiet;
        quiet.threads = o.threads;
        const Field expected = evaluate_grid(*model, grid, *reference, quiet);
        report << compare_report(field, engine->description(), expected, reference->description());
    }

    if (!o.stats && o.output.empty() && o.mimages.empty() && o.contour.empty() && !o.compare && o.steps.empty()) {
        report << fmt::format("{} {} with {} in {}: inside {}, boundary {}, outside {}, invalid {}; "
                                 "values in [{}, {}] (write them with -o FILE)\n",
                                 shown_script_name(o.positional[0]), grid_text(grid), engine->name(),
                                 format_duration(eval_seconds), stats.positive, stats.zero, stats.negative,
                                 stats.invalid, stats.min, stats.max);
    }
    if (o.stats) {
        const IrStats s = ir_stats(*model);
        report << fmt::format(
            "model: {}\ngrid: {} = {} points, x [{}, {}], y [{}, {}]{}\n"
            "nodes: {} ({} operations), shared: {}, hash-consing reuses: {}\n"
            "classic cost: {} operations per point; voxel: {}{}\n"
            "engine: {}{}, threads: {}\n"
            "isa: lane loops {}, compiled tapes {}, float32 transcendentals {} ({})\n"
            "time: compile {:.3f} s, evaluate {:.3f} s, write {:.3f} s\n"
            "speed: {} points/s\n"
            "values: min {}, max {}, inside {}, boundary {}, outside {}, invalid {}\n"
            "peak memory: {} evaluating, {} in all\n",
            shown_script_name(o.positional[0]), grid_text(grid), format_operations(double(grid.points())), grid.x.min, grid.x.max,
            grid.y.min, grid.y.max, grid.dims == 3 ? fmt::format(", z [{}, {}]", grid.z.min, grid.z.max) : "",
            s.nodes, s.operations, s.shared, s.reuses, format_operations(s.classic_operations),
            format_operations(double(s.operations)),
            can.hoists ? hoisted_text(s) : "", engine->name(),
            can.sign_only ? " (interval sign renderer)" : can.float32 ? " (float32)" : "", o.threads > 0 ? o.threads : int(std::max(1u, std::thread::hardware_concurrency())),
            lane_loop_isa(), !tape_jit_available() ? "none" : o.engine_settings.compile ? jit_width_name(tape_jit_width()) : "off (--no-jit)",
            vector_math::isa_name(vector_math::active_isa()), vector_math::libraries_text(), compile_seconds, eval_seconds, write_seconds,
            format_operations(eval_seconds > 0 ? double(grid.points()) / eval_seconds : 0.0),
            stats.min, stats.max, stats.positive, stats.zero, stats.negative, stats.invalid,
            format_bytes(eval_peak), format_bytes(peak_rss_bytes()));
    }
    return 0;
}

}  // namespace
}  // namespace fortu

int main(int argc, char** argv) {
    using namespace fortu;
    tune_allocator();
    std::vector<std::string> args(argv + 1, argv + argc);
    try {
        // Commands with options of their own parse their own arguments.
        if (!args.empty()) {
            const std::vector<std::string> rest(args.begin() + 1, args.end());
            if (args[0] == "golden") return run_golden_command(rest);
            if (args[0] == "bench") return run_bench_command(rest);
            if (args[0] == "repl") return run_repl_command(rest);
        }
        CliOptions o = parse_command_line(args);
        if (o.command == "help") { std::cout << (o.help.empty() ? usage_text() : o.help); return 0; }
        if (o.command == "version") { std::cout << version_text(); return 0; }
        if (o.command == "check") return command_check(o);
        if (o.command == "ir") return command_ir(o);
        if (o.command == "eval") return command_eval(o);
        if (o.command == "singular") return command_singular(o);
        return command_run(o);
    } catch (const UsageError& e) {
        std::cerr << "fortu: error: " << e.what() << "\n";
        return kExitUsage;
    } catch (const std::bad_alloc&) {
        std::cerr << "fortu: error: out of memory\n";
        return kExitModelError;
    } catch (const std::exception& e) {
        std::cerr << "fortu: error: " << e.what() << "\n";
        return kExitModelError;
    }
}
