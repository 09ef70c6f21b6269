// cli/bench/bench.cpp — `fortu bench`: its command line, and the MODEL... mode (each model × engine
// × size measured, printed as a table with classic/voxel ratios, optionally written as JSON,
// CSV and an SVG plot). `--paper` hands over to bench_paper.cpp, `--performance` to
// bench_performance.cpp.
#include "cli/bench/bench_measure.hpp"
#include "cli/bench/bench_mesh.hpp"
#include "cli/bench/bench_paper.hpp"
#include "cli/bench/bench_performance.hpp"
#include "cli/bench/bench_report.hpp"
#include "cli/option_table.hpp"
#include "cli/cli_options.hpp"
#include "cli/commands.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/output_error.hpp"
#include "runtime/plot.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <sys/ioctl.h>
#include <unistd.h>

namespace fortu {
namespace {

constexpr std::string_view kBenchUsage = R"(usage:
  fortu bench MODEL... [options]   time each model x engine x size (bench/README.md)
  fortu bench --paper [--quick] [--out DIR] [--examples DIR] [--repeat N] [--threads N] [--budget OPS]
                                   the papers' experiments E1-E5: results.md, results.json, plots
  fortu bench --performance [--quick] [--data DIR] [--out DIR] [--examples DIR] [--repeat N] [--threads N]
                                   the performance suite (prospero.vm, 64-segment FLOZ, Fig. 3a with
                                   M-images) beside its targets: results.md, results.json
                                   (default --out bench-results/perf, --repeat 5)
)";

constexpr int kMaxBenchNodes = 20000;   // per axis; the grid itself is capped by kMaxGridPoints

struct BenchArgs {
    std::vector<std::string> models;
    std::vector<const Engine*> engines{&engine_named("classic"), &engine_named("voxel")};
    std::vector<int> sizes{200, 400, 800};
    MeasureOptions measure;
    std::string json, csv, plot;
    bool paper = false, performance = false, quick = false;
    bool mesh = false;   ///< --mesh: time the mesher instead of the engines
    std::string out_dir, examples_dir, data_dir;
    bool sizes_given = false, engines_given = false, repeat_given = false;

    /// "--paper", "--performance", or nullptr for the MODEL... mode.
    const char* suite() const { return paper ? "--paper" : performance ? "--performance" : nullptr; }
};

long parse_integer(const std::string& option, const std::string& text, long lo, long hi) {
    try {
        std::size_t used = 0;
        const long v = std::stol(text, &used);
        if (used == text.size() && v >= lo && v <= hi) return v;
    } catch (...) {
    }
    throw UsageError(fmt::format("{}: '{}' is not an integer in {}..{}", option, text, lo, hi));
}

/// `fortu bench`'s option table, writing into `b`.
OptionTable bench_options(BenchArgs& b) {
    OptionTable t("bench", std::string(kBenchUsage));
    t.option("--engines", "E1,E2", "what to time (default classic,voxel), of:" + engine_summaries(),
             [&b](const std::string& list) {
                 b.engines.clear();
                 b.engines_given = true;
                 for (const std::string& name : split_value(list, ',')) {
                     const Engine* engine = find_engine(name);
                     if (!engine) throw UsageError(fmt::format("--engines: unknown engine '{}' ({})", name, engine_names()));
                     b.engines.push_back(engine);
                 }
             });
    t.flag("--mimages", "each run also computes the M-images (the FV model's components)\n"
                        "after the evaluation; not for sign cells",
           [&b] { b.measure.mimages = true; });
    t.option("--sizes", "200,400,800", "nodes per axis (N means NxN, or NxNxN for a 3D model)",
             [&b](const std::string& list) {
                 b.sizes.clear();
                 b.sizes_given = true;
                 for (const std::string& n : split_value(list, ',')) b.sizes.push_back(int(parse_integer("--sizes", n, 2, kMaxBenchNodes)));
             });
    t.option("--repeat", "N", "timed runs per cell (default 3; a cell stops repeating after 20 s)",
             [&b](const std::string& v) {
                 b.measure.repeat = int(parse_integer("--repeat", v, 1, 1000));
                 b.repeat_given = true;
             });
    t.option("--budget", "OPS", "classic cells above OPS operations are skipped, with their\n"
                                "estimated time printed (default 2e10)",
             [&b](const std::string& text) {
                 char* end = nullptr;
                 const double v = std::strtod(text.c_str(), &end);
                 if (text.empty() || *end != '\0' || !std::isfinite(v) || v <= 0)
                     throw UsageError(fmt::format("--budget: '{}' is not a positive number of operations", text));
                 b.measure.budget = v;
             });
    add_isa_option(t);
    t.option("--threads", "N", "worker threads (default: all cores)",
             [&b](const std::string& v) { b.measure.threads = int(parse_integer("--threads", v, 0, 1024)); });
    t.option("--json", "FILE", "the results as JSON (schema fortu-bench/1)", [&b](const std::string& v) { b.json = v; });
    t.option("--csv", "FILE", "one row per cell", [&b](const std::string& v) { b.csv = v; });
    t.option("--plot", "FILE.svg", "median time against grid points, one line per model and engine",
             [&b](const std::string& v) {
                 b.plot = v;
                 if (b.plot.size() < 4 || b.plot.substr(b.plot.size() - 4) != ".svg")
                     throw UsageError(fmt::format("--plot: '{}' must end in .svg (fortu writes SVG plots)", b.plot));
             });
    t.flag("--mesh", "time meshing (fortu run -o F.stl) of each 3D MODEL at each size\n"
                     "instead of the engines: triangles, time, peak memory",
           [&b] { b.mesh = true; });
    t.flag("--paper", "the papers' experiments E1-E5", [&b] { b.paper = true; });
    t.flag("--performance", "the performance suite beside its targets", [&b] { b.performance = true; });
    t.flag("--quick", "--paper / --performance on small grids (a smoke run)", [&b] { b.quick = true; });
    t.option("--out", "DIR", "where --paper / --performance write (default bench-results[/perf])",
             [&b](const std::string& v) {
                 b.out_dir = v;
                 if (b.out_dir.empty()) throw UsageError("--out: give a folder name");
             });
    t.option("--examples", "DIR", "the papers' example models (default: FORTU_EXAMPLES, else the\n"
                                  "source tree's examples/, else the installed ones)",
             [&b](const std::string& v) { b.examples_dir = v; });
    t.option("--data", "DIR", "the folder with prospero.vm (--performance; default:\n"
                              "$FORTU_SHARED_DIR/data, else the one configured at build time)",
             [&b](const std::string& v) { b.data_dir = v; });
    t.positionals(b.models);
    return t;
}

/// Parses `fortu bench`'s arguments; nullopt for --help (printed).
std::optional<BenchArgs> parse_bench_args(const std::vector<std::string>& args) {
    BenchArgs b;
    const OptionTable table = bench_options(b);
    if (!table.parse(args)) {
        std::cout << table.help();
        return std::nullopt;
    }
    if (b.paper && b.performance) throw UsageError("'fortu bench': --paper and --performance are two runs; give one");
    const char* suite = b.suite();
    if (b.paper && !b.models.empty())
        throw UsageError("'fortu bench --paper' runs the papers' models; give no MODEL with it");
    if (b.performance && !b.models.empty())
        throw UsageError("'fortu bench --performance' runs its own suite of models; give no MODEL with it");
    if (!suite && b.models.empty())
        throw UsageError("'fortu bench': give at least one MODEL, or --paper, or --performance");
    if (!suite && (b.quick || !b.out_dir.empty() || !b.examples_dir.empty()))
        throw UsageError("'fortu bench': --quick, --out and --examples go with --paper or --performance");
    if (!b.performance && !b.data_dir.empty()) throw UsageError("'fortu bench': --data goes with --performance");
    if (suite && (b.sizes_given || !b.json.empty() || !b.csv.empty() || !b.plot.empty()))
        throw UsageError(fmt::format("'fortu bench {}' chooses its own sizes and writes its files to --out DIR", suite));
    if (suite && (b.engines_given || b.measure.mimages))
        throw UsageError(fmt::format("'fortu bench {}' chooses what it times; --engines and --mimages go with MODEL...",
                                     suite));
    return b;
}

/// One plot of the MODEL mode: median time against points, a series per model and engine,
/// named by the model's short name so the legend tells the lines apart.
Plot bench_plot(const std::vector<BenchCell>& cells) {
    Plot plot;
    plot.title = "fortu bench: time against grid size";
    plot.x_label = "grid points";
    plot.y_label = "wall time (s)";
    plot.log_x = plot.log_y = true;
    for (const BenchCell& c : cells) {
        if (c.skipped) continue;
        const std::string name = fmt::format("{} ({})", c.shown_name(), c.engine->name());
        auto it = std::find_if(plot.series.begin(), plot.series.end(), [&](const PlotSeries& s) { return s.name == name; });
        if (it == plot.series.end()) it = plot.series.insert(plot.series.end(), PlotSeries{name});
        it->points.emplace_back(double(c.points()), c.median);
    }
    return plot;
}

/// A cell is announced (its estimate on stderr when stdout is not a terminal) from this long on.
constexpr double kAnnounceSeconds = 5.0;
/// Classic cells under this many operations take well under a second: no calibration run for them.
constexpr double kEstimateFromOperations = 3e7;

/// What `cell` will take in all, its repeats stopping at the cap as measure_cell's do; < 0
/// when unknown. Classic: its operations at the measured (or calibrated) classic rate; others:
/// the last measured cell of the same model and engine, scaled by the points.
double planned_seconds(const BenchCell& cell, const MeasureOptions& o, ClassicRate& rate,
                       const std::vector<BenchCell>& done) {
    double one = -1;
    if (cell.engine->capabilities().expanded_tree_cost) {
        const double operations = cell.total_operations();
        if (operations > o.budget || operations < kEstimateFromOperations) return -1;
        const double per_operation = rate.seconds_per_operation(o.threads);
        if (per_operation > 0) one = per_operation * operations;
    } else {
        for (const BenchCell& c : done)
            if (c.model == cell.model && c.engine == cell.engine && !c.skipped && c.median > 0 && c.points())
                one = c.median * double(cell.points()) / double(c.points());
    }
    if (one <= 0) return -1;
    const double runs = std::min(double(std::max(1, o.repeat)), std::max(1.0, std::ceil(o.repeat_cap / one)));
    return one * runs;
}

/// The terminal's width in columns, or 0 when stdout is not a terminal.
int terminal_columns() {
    if (!isatty(STDOUT_FILENO)) return 0;
    winsize ws{};
    return ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 ? ws.ws_col : 80;
}

int run_models(const BenchArgs& b) {
    // Every model loaded and every grid checked first: errors come before any timing, and the
    // table's columns are known before its header is printed.
    struct Loaded {
        std::string path, label;
        Model model;
    };
    std::vector<Loaded> models;
    int status = 0;
    for (const std::string& path : b.models) {
        std::optional<Model> model = load_bench_model(path);
        if (!model) { status = 1; continue; }
        models.push_back({path, "", std::move(*model)});
    }
    std::vector<std::string> paths;
    for (const Loaded& m : models) paths.push_back(m.path);
    const std::vector<std::string> labels = model_labels(paths);
    std::vector<std::pair<const Loaded*, BenchCell>> planned;
    for (std::size_t i = 0; i < models.size(); ++i) {
        models[i].label = labels[i];
        for (int size : b.sizes) {
            const Grid grid = bench_grid(models[i].model, size);
            if (double(grid.points()) > double(kMaxGridPoints))
                throw UsageError(fmt::format("--sizes: {} is {} points, more than the {} fortu allocates",
                                             grid_text(grid), format_count(grid.points()), format_count(kMaxGridPoints)));
            for (const Engine* engine : b.engines) {
                BenchCell cell = plan_cell(models[i].path, models[i].model, grid, *engine);
                cell.label = labels[i];
                planned.emplace_back(&models[i], std::move(cell));
            }
        }
    }
    if (planned.empty()) return status;

    std::vector<BenchCell> plan;
    for (const auto& p : planned) plan.push_back(p.second);
    const BenchTableLayout layout = bench_table_layout(plan, b.measure.mimages);
    const int columns = terminal_columns();
    std::cout << bench_table_header(layout) << std::flush;
    std::vector<BenchCell> cells;
    ClassicRate rate;
    for (const auto& [loaded, cell] : planned) {
        // Before each cell: on a terminal a progress line the row then replaces; otherwise the
        // rows stay plain (for files and pipes) and only a long cell is announced, on stderr.
        const double expected = planned_seconds(cell, b.measure, rate, cells);
        const std::string what = fmt::format("{} {} {}", cell.engine->name(), grid_text(cell.grid), cell.label);
        const std::string about = expected >= 1 ? fmt::format(": about {}", estimate_text(expected)) : "";
        if (columns > 0) {
            std::string progress = fmt::format("timing {}{}...", what, about);
            if (int(progress.size()) >= columns) progress = progress.substr(0, std::size_t(std::max(columns - 4, 1))) + "...";
            std::cout << progress << std::flush;
        } else if (expected >= kAnnounceSeconds) {
            std::cerr << fmt::format("fortu: note: timing {}{}\n", what, about) << std::flush;
        }
        BenchCell measured = measure_cell(loaded->path, loaded->model, cell.grid, *cell.engine, b.measure, rate);
        measured.label = cell.label;
        if (columns > 0) std::cout << "\r\033[K";
        std::cout << bench_table_row(layout, measured) << std::flush;
        cells.push_back(std::move(measured));
    }
    std::cout << ratio_text(bench_ratios(cells));
    try {
        if (!b.json.empty()) {
            const std::string json = bench_json(cells, describe_machine(), b.measure);
            write_file_atomically(b.json, [&](OutputFile& f) { f.write(json); });
        }
        if (!b.csv.empty()) {
            const std::string csv = bench_csv(cells);
            write_file_atomically(b.csv, [&](OutputFile& f) { f.write(csv); });
        }
        if (!b.plot.empty()) write_plot_svg(bench_plot(cells), b.plot);
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return 1;
    }
    return status;
}

}  // namespace

int run_bench_command(const std::vector<std::string>& args) {
    const std::optional<BenchArgs> parsed = parse_bench_args(args);
    if (!parsed) return 0;
    const BenchArgs& b = *parsed;
    if (b.mesh && (b.suite() || b.engines_given || b.measure.mimages || !b.json.empty() || !b.csv.empty() || !b.plot.empty()))
        throw UsageError("'fortu bench --mesh' times the mesher on MODEL... (--sizes, --repeat, --threads)");
    if (b.mesh) return run_mesh_benchmarks(b.models, b.sizes_given ? b.sizes : std::vector<int>{65, 129}, b.measure);
    if (b.performance) {
        PerformanceOptions p;
        p.quick = b.quick;
        if (!b.out_dir.empty()) p.out_dir = b.out_dir;
        p.data_dir = b.data_dir;
        p.examples_dir = b.examples_dir;
        p.measure = b.measure;
        if (!b.repeat_given) p.measure.repeat = 5;
        return run_performance_benchmarks(p);
    }
    if (!b.paper) return run_models(b);
    PaperOptions p;
    p.quick = b.quick;
    if (!b.out_dir.empty()) p.out_dir = b.out_dir;
    p.examples_dir = b.examples_dir;
    p.measure = b.measure;
    // The paper run has ten minutes in all: slow cells repeat less than in the MODEL mode.
    p.measure.repeat_cap = b.quick ? 5.0 : 10.0;
    if (b.quick) p.cell_cap = 5.0;
    return run_paper_benchmarks(p);
}

}  // namespace fortu
