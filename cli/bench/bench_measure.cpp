// cli/bench/bench_measure.cpp — timing one bench cell. Peak memory per cell: the kernel's peak-RSS
// mark (VmHWM) is reset through /proc/self/clear_refs before the cell and read after it, so
// each cell reports its own peak, not the process's; where that is refused, the process's
// ru_maxrss growth over the cell is reported instead (memory_method() says which; PeakMemoryProbe).
#include "cli/bench/bench_measure.hpp"

#include "cli/data_paths.hpp"

#include "grammar/diagnostic.hpp"
#include "interp/classic_cost.hpp"
#include "interp/ir_print.hpp"
#include "interp/lower.hpp"
#include "interp/tape.hpp"
#include "interp/vm_import.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <numbers>
#include <time.h>

namespace fortu {
namespace {

constexpr double kCalibrationOperations = 2e7;

std::optional<Model> compile_source(std::shared_ptr<SourceFile> source) {
    DiagnosticSink sink;
    CompileOptions options;
    options.include_dirs = stdlib_dirs();
    std::optional<Model> model =
        is_vm_path(source->path()) ? import_vm(source, sink) : compile(source, options, sink);
    for (const Diagnostic& d : sink.diagnostics())
        if (d.severity != Severity::Note) std::cerr << render(d);
    return model;
}

}  // namespace

std::filesystem::path examples_folder(const std::string& given) {
    if (!given.empty()) return given;
    return examples_dir();
}

std::optional<Model> load_bench_model(const std::string& path) {
    std::string error;
    auto source = SourceFile::load(path, error);
    if (!source) {
        std::cerr << fmt::format("fortu: error: {}\n", error);
        return std::nullopt;
    }
    return compile_source(source);
}

std::optional<Model> compile_bench_text(const std::string& name, const std::string& text) {
    return compile_source(std::make_shared<SourceFile>(name, text));
}

std::string floz_steps_text(int steps) {
    // An open polyline on a 24-gon turned by 0.1 rad: no two vertices share an x or a y, so
    // hash-consing shares nothing between steps but the one common vertex, and every step adds
    // the same operations (9 on the voxel tape) — the line E3 fits is then the engine's, not
    // the polygon's symmetry.
    constexpr int kSides = 24;
    constexpr double kTurn = 0.1;
    auto vertex = [](int k) {
        const double a = 2 * std::numbers::pi * k / kSides + kTurn;
        return fmt::format("{:.6f}, {:.6f}", 0.8 * std::cos(a), 0.8 * std::sin(a));
    };
    std::string text = fmt::format("// E3: {} flozation step(s) along a regular {}-gon\nARGUMENT X, Y;\n"
                                   "INCLUDE 'floz.fortu'\nVARIABLE W = FLOZ2(X, Y, {}, {});\n",
                                   steps, kSides, vertex(0), vertex(1));
    for (int i = 1; i <= steps; ++i) text += fmt::format("W = W & FLOZ2(X, Y, {}, {});\n", vertex(i), vertex(i + 1));
    return text + "RETURN W;\n";
}

Grid bench_grid(const Model& model, int nodes) {
    Grid grid;
    grid.dims = model.dims();
    Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
    for (int a = 0; a < 3; ++a) {
        AxisRange r{-1.0, 1.0};
        if (a < int(model.arguments.size()) && model.ranges[a]) r = *model.ranges[a];
        axes[a]->min = r.min;
        axes[a]->max = r.max;
        axes[a]->nodes = a < grid.dims ? nodes : 1;
    }
    if (model.arguments.size() == 1) grid.y.nodes = 1;
    return grid;
}

double median_of(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}


void ClassicRate::observe(const BenchCell& cell, int threads) {
    if (!cell.engine->capabilities().expanded_tree_cost || cell.skipped || cell.median <= 0) return;
    Known& k = known_[threads];
    if (cell.total_operations() < k.operations) return;
    k.operations = cell.total_operations();
    k.seconds_per_operation = cell.median / cell.total_operations();
}

double ClassicRate::seconds_per_operation(int threads) {
    Known& k = known_[threads];
    if (k.seconds_per_operation > 0) return k.seconds_per_operation;
    // Nothing measured yet: time the classic engine on E3's 8-step polygon on a grid sized
    // to about kCalibrationOperations operations (well under a second).
    std::optional<Model> model = compile_bench_text("<calibration>", floz_steps_text(8));
    if (!model) return -1;
    const double per_point = classic_operations_per_point(model->graph, model->root);
    const int nodes = std::max(2, int(std::sqrt(kCalibrationOperations / per_point)));
    const Grid grid = bench_grid(*model, nodes);
    EvalOptions eval;
    eval.threads = threads;
    Stopwatch clock;
    evaluate_grid(*model, grid, engine_named("classic"), eval);
    k.seconds_per_operation = clock.seconds() / (per_point * double(grid.points()));
    return k.seconds_per_operation;
}

namespace {

void set_operations(BenchCell& cell, const Model& model) {
    cell.operations_per_point = cell.engine->capabilities().expanded_tree_cost
                                    ? classic_operations_per_point(model.graph, model.root)
                                    : double(compile_tape(model.graph, model.root).code.size());
}

/// CPU time of the whole process (all its threads), in seconds.
double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// M-images of a sign image would be planes through ±1 steps: sign cells never compute them.
bool computes_mimages(const Engine& engine, const MeasureOptions& options) {
    return options.mimages && !engine.capabilities().sign_only;
}

/// One timed run of a cell, appended to its seconds, CPU seconds and M-image seconds.
void timed_run(BenchCell& cell, const Model& model, const MeasureOptions& options) {
    EvalOptions eval;
    eval.threads = options.threads;
    const double cpu = process_cpu_seconds();
    Stopwatch clock;
    const Field field = evaluate_grid(model, cell.grid, *cell.engine, eval);
    if (computes_mimages(*cell.engine, options)) {
        Stopwatch mimages_clock;
        const FvModel fv(field);   // the normalised components n1..n_{dims+2}: the M-images' values
        cell.mimages_seconds.push_back(mimages_clock.seconds());
        cell.mimages = fv.components();
    }
    cell.seconds.push_back(clock.seconds());
    cell.cpu_seconds.push_back(process_cpu_seconds() - cpu);
}

void summarise(BenchCell& cell) {
    cell.cpu_median = median_of(cell.cpu_seconds);
    cell.mimages_median = median_of(cell.mimages_seconds);
    cell.min = *std::min_element(cell.seconds.begin(), cell.seconds.end());
    cell.max = *std::max_element(cell.seconds.begin(), cell.seconds.end());
    cell.median = median_of(cell.seconds);
}

BenchCell new_cell(const std::string& name, const Model& model, const Grid& grid, const Engine& engine) {
    BenchCell cell;
    cell.model = name;
    cell.engine = &engine;
    cell.grid = grid;
    set_operations(cell, model);
    return cell;
}

}  // namespace

BenchCell plan_cell(const std::string& name, const Model& model, const Grid& grid, const Engine& engine) {
    return new_cell(name, model, grid, engine);
}

std::vector<BenchCell> measure_interleaved(const std::vector<SeriesEntry>& entries, const Engine& engine,
                                           const MeasureOptions& options) {
    std::vector<BenchCell> cells;
    for (const SeriesEntry& entry : entries) cells.push_back(new_cell(entry.name, *entry.model, entry.grid, engine));
    const PeakMemoryProbe memory;
    for (int round = 0; round < std::max(1, options.repeat); ++round)
        for (std::size_t i = 0; i < entries.size(); ++i) timed_run(cells[i], *entries[i].model, options);
    for (BenchCell& c : cells) {
        c.peak_rss_bytes = memory.peak();
        c.rss_growth_bytes = memory.growth();
        summarise(c);
    }
    return cells;
}

BenchCell measure_cell(const std::string& name, const Model& model, const Grid& grid, const Engine& engine,
                       const MeasureOptions& options, ClassicRate& rate) {
    BenchCell cell = new_cell(name, model, grid, engine);
    if (engine.capabilities().expanded_tree_cost) {
        const int depth = dag_depth(model.graph, model.root);
        if (depth > kClassicMaxDepth) {
            cell.skipped = true;
            cell.skip_reason = fmt::format("nested {} levels deep; the classic engine's recursion stops at {}",
                                           depth, kClassicMaxDepth);
        } else if (cell.total_operations() > options.budget) {
            cell.skipped = true;
            cell.skip_reason = fmt::format("{:.3g} operations, over the budget of {:.3g}", cell.total_operations(),
                                           options.budget);
        }
        if (cell.skipped) {
            const double per_operation = rate.seconds_per_operation(options.threads);
            if (per_operation > 0) cell.estimated_seconds = per_operation * cell.total_operations();
            return cell;
        }
    }

    const PeakMemoryProbe memory;
    double total = 0;
    for (int i = 0; i < std::max(1, options.repeat); ++i) {
        if (i > 0 && total >= options.repeat_cap) break;
        timed_run(cell, model, options);
        total += cell.seconds.back();
    }
    cell.peak_rss_bytes = memory.peak();
    cell.rss_growth_bytes = memory.growth();
    summarise(cell);
    rate.observe(cell, options.threads);
    return cell;
}

}  // namespace fortu
