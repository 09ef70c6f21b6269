// cli/bench/bench_paper.cpp — the papers' experiments (fv-method.md §4). Each experiment measures
// its cells, then renders a Markdown section (our numbers beside the paper's), a JSON object
// and, for the growth experiments, a plot with least-squares fits: E3 fits ln t = a + n·ln g
// for classic (the expanded tree doubles with each R0 conjunction, g ≈ 2) and t = a + b·n for
// voxel (one FLOZ and one conjunction more per step); E4 fits t = a + b·points for both.
#include "cli/bench/bench_paper.hpp"

#include "cli/bench/bench_report.hpp"
#include "interp/classic_cost.hpp"
#include "interp/ir_print.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/output_error.hpp"
#include "runtime/plot.hpp"
#include "runtime/resources.hpp"

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <limits>

namespace fortu {
namespace {

constexpr double kPaperFig3aClassic = 1049, kPaperFig3aVoxel = 111;   // 17 min 29 s, 1 min 51 s
constexpr double kPaperPolygonTotal = 30, kPaperPolygonStep = 2;      // ≤ 30 s, ≈ 2 s per step
constexpr int kMaxSteps = 16;
constexpr int kVoxelStepRepeats = 15;   // E3's voxel cells take milliseconds: more runs, steadier medians
constexpr double kDeadline = 540, kQuickDeadline = 60;   // the acceptance: under 10 minutes
constexpr double kFitMinSeconds = 0.01;   // E3 classic cells faster than this are fixed overhead
// The fv engine (the papers' method, P = 256) takes ~1000x the voxel engine's time:
// its cells run once each, or they alone would take most of the run.
MeasureOptions fv_measure(MeasureOptions m) {
    m.repeat = 1;
    return m;
}

struct Experiment {
    Experiment(std::string id_in, std::string title_in) : id(std::move(id_in)), title(std::move(title_in)) {}
    std::string id;
    std::string title;
    std::vector<BenchCell> cells;
    std::string markdown;
    std::string summary_json = "{}";
};

struct Context {
    const PaperOptions& options;
    std::filesystem::path examples;
    ClassicRate rate;
    double deadline = 0;   ///< seconds since start after which no classic cell may still run
    Stopwatch clock;
    bool failed = false;
};

std::optional<Model> load_example(Context& ctx, const std::string& file) {
    std::optional<Model> model = load_bench_model((ctx.examples / file).string());
    if (!model) ctx.failed = true;
    return model;
}

BenchCell run_cell(Context& ctx, const std::string& name, const Model& model, const Grid& grid, const Engine& engine,
                   const MeasureOptions& measure) {
    // The whole run must end in time on a loaded machine: a classic cell whose estimate
    // (operations × the classic speed measured so far) would pass the deadline is not run.
    const double operations = classic_operations_per_point(model.graph, model.root) * double(grid.points());
    if (engine.capabilities().expanded_tree_cost && operations <= measure.budget) {
        const double estimate = ctx.rate.seconds_per_operation(measure.threads) * operations;
        const double left = ctx.deadline - ctx.clock.seconds();
        if (estimate > left) {
            BenchCell c;
            c.model = name;
            c.engine = &engine;
            c.grid = grid;
            c.operations_per_point = operations / double(grid.points());
            c.skipped = true;
            c.skip_reason = fmt::format("would pass the run's {} time limit", format_duration(ctx.deadline));
            c.estimated_seconds = estimate;
            std::cerr << fmt::format("bench: {} classic {}: skipped, {}\n", name, grid_text(grid), c.skip_reason);
            return c;
        }
    }
    std::cerr << fmt::format("bench: {} {} {} ...\n", name, engine.name(), grid_text(grid));
    return measure_cell(name, model, grid, engine, measure, ctx.rate);
}

std::string time_md(const BenchCell& c) {
    if (c.skipped)
        return fmt::format("skipped ({}), estimated {}", c.skip_reason,
                           estimate_text(c.estimated_seconds));
    return fmt::format("{} ({} run{})", format_duration(c.median), c.seconds.size(), c.seconds.size() == 1 ? "" : "s");
}

double cell_seconds(const BenchCell& c) { return c.skipped ? c.estimated_seconds : c.median; }

std::string quick_note(const Context& ctx, const std::string& paper_size) {
    return ctx.options.quick ? fmt::format(" (--quick: smaller than the paper's {}, not comparable)", paper_size) : "";
}

Experiment e1_fig3a(Context& ctx) {
    Experiment e{"E1", "S1 Fig. 3a non-convex contour"};
    const int size = ctx.options.quick ? 200 : 800;
    auto formula = load_example(ctx, "s1_fig3a_formula.fortu");
    auto floz = load_example(ctx, "s1_fig3a_floz.fortu");
    if (!formula || !floz) {
        e.markdown = "Not run: the Fig. 3a example models did not load (see the errors above).\n";
        return e;
    }
    // The comparison needs all four cells: the budget does not apply (E4 reuses the 800² ones).
    MeasureOptions m = ctx.options.measure;
    m.budget = std::numeric_limits<double>::infinity();
    e.cells.push_back(run_cell(ctx, "s1_fig3a_formula.fortu", *formula, bench_grid(*formula, size), engine_named("classic"), m));
    e.cells.push_back(run_cell(ctx, "s1_fig3a_floz.fortu", *floz, bench_grid(*floz, size), engine_named("voxel"), m));
    e.cells.push_back(run_cell(ctx, "s1_fig3a_floz.fortu", *floz, bench_grid(*floz, size), engine_named("classic"), m));
    e.cells.push_back(run_cell(ctx, "s1_fig3a_formula.fortu", *formula, bench_grid(*formula, size), engine_named("voxel"), m));
    e.cells.push_back(run_cell(ctx, "s1_fig3a_floz.fortu", *floz, bench_grid(*floz, size), engine_named("fv"), fv_measure(m)));
    const char* paper[] = {"17 min 29 s (1049 s)", "1 min 51 s (111 s)", "—", "—", "1 min 51 s (111 s)"};
    const char* what[] = {"classic, formula (3)", "voxel, FLOZ-construction", "classic, FLOZ-construction",
                          "voxel, formula (3)", "fv (the papers' method, P = 256), FLOZ-construction"};
    e.markdown = fmt::format("Grid {}x{}{}.\n\n| cell | operations per point | ours (median) | paper |\n|---|---|---|---|\n",
                             size, size, quick_note(ctx, "800x800"));
    for (int i = 0; i < 5; ++i)
        e.markdown += fmt::format("| {} | {} | {} | {} |\n", what[i], format_operations(e.cells[i].operations_per_point),
                                  time_md(e.cells[i]), paper[i]);
    const double ratio = cell_seconds(e.cells[0]) / e.cells[1].median;
    const double floz_ratio = cell_seconds(e.cells[2]) / e.cells[1].median;
    e.markdown += fmt::format(
        "\nRatio classic formula (3) / voxel FLOZ: ours {:.3g}, paper {:.3g}. Classic / voxel on the same "
        "FLOZ-construction: {:.3g}. Classic formula (3) / fv FLOZ (the papers' two methods): {:.3g}.\n",
        ratio, kPaperFig3aClassic / kPaperFig3aVoxel, floz_ratio, cell_seconds(e.cells[0]) / e.cells[4].median);
    e.summary_json = fmt::format(
        "{{\"size\": [{0}, {0}], \"paper_classic_seconds\": {1}, \"paper_voxel_seconds\": {2}, "
        "\"paper_ratio\": {3}, \"ratio_classic_formula_over_voxel_floz\": {4}, "
        "\"ratio_classic_floz_over_voxel_floz\": {5}}}",
        size, kPaperFig3aClassic, kPaperFig3aVoxel, json_number(kPaperFig3aClassic / kPaperFig3aVoxel),
        json_number(ratio), json_number(floz_ratio));
    return e;
}

int r_operation_count(const Model& model) {
    int count = 0;
    for (ir::NodeId id : model.graph.reachable(model.root))
        if (ir::op_flags(model.graph.node(id).op) & ir::kROperation) ++count;
    return count;
}

Experiment e2_polygon(Context& ctx) {
    Experiment e{"E2", "Rvachev's 14-vertex polygon, FV flozation"};
    const int size = ctx.options.quick ? 200 : 400;
    auto model = load_example(ctx, "lrfm_polygon14.fortu");
    if (!model) {
        e.markdown = "Not run: examples/lrfm_polygon14.fortu did not load (see the errors above).\n";
        return e;
    }
    const Grid grid = bench_grid(*model, size);
    e.cells.push_back(run_cell(ctx, "lrfm_polygon14.fortu", *model, grid, engine_named("voxel"), ctx.options.measure));
    e.cells.push_back(run_cell(ctx, "lrfm_polygon14.fortu", *model, grid, engine_named("classic"), ctx.options.measure));
    e.cells.push_back(run_cell(ctx, "lrfm_polygon14.fortu", *model, grid, engine_named("fv"), fv_measure(ctx.options.measure)));
    const int steps = std::max(1, r_operation_count(*model));
    const double total = e.cells[0].median, per_step = total / steps;
    const double fv_total = e.cells[2].median, fv_per_step = fv_total / steps;
    e.markdown = fmt::format(
        "Grid {0}x{0}{1}; {2} flozation steps (R-operations in the model).\n\n"
        "| | ours | paper |\n|---|---|---|\n"
        "| voxel flozation, total | {3} | ≤ 30 s |\n| voxel, per step | {4} | ≈ 2 s |\n"
        "| classic (all-analytic) | {5} | ~100× slower than the recursive formula |\n"
        "| fv (the papers' method, P = 256), total | {6} | ≤ 30 s |\n| fv, per step | {7} | ≈ 2 s |\n"
        "| fv, peak memory (the whole process) | {8} | — |\n",
        size, quick_note(ctx, "400x400"), steps, time_md(e.cells[0]), format_duration(per_step), time_md(e.cells[1]),
        time_md(e.cells[2]), format_duration(fv_per_step), format_bytes(e.cells[2].peak_rss_bytes));
    e.summary_json = fmt::format(
        "{{\"size\": [{0}, {0}], \"steps\": {1}, \"voxel_seconds\": {2}, \"voxel_seconds_per_step\": {3}, "
        "\"paper_total_seconds_max\": {4}, \"paper_seconds_per_step\": {5}, \"fv_seconds\": {6}, "
        "\"fv_seconds_per_step\": {7}}}",
        size, steps, json_number(total), json_number(per_step), kPaperPolygonTotal, kPaperPolygonStep,
        json_number(fv_total), json_number(fv_per_step));
    return e;
}

Experiment e3_steps(Context& ctx, const std::string& out_dir) {
    Experiment e{"E3", "growth with the number of flozation steps"};
    const int size = ctx.options.quick ? 100 : 300;
    const double cap = ctx.options.cell_cap;
    // One thread for both engines: millisecond voxel cells on a shared 2-core machine are
    // otherwise bimodal (a worker waiting for a busy core), which bends a straight line.
    MeasureOptions classic = ctx.options.measure;
    classic.threads = 1;
    classic.budget = std::numeric_limits<double>::infinity();   // the per-cell time cap rules here
    MeasureOptions voxel = ctx.options.measure;
    voxel.threads = 1;
    voxel.repeat = std::max(voxel.repeat, kVoxelStepRepeats);   // millisecond cells: more runs for a steady median
    // t_*: ln(CPU time) or CPU time, fitted; w_*: the same from wall time, printed beside.
    std::vector<double> n_classic, t_classic, w_classic, n_all_classic, t_all_classic, w_all_classic;
    std::vector<double> n_voxel, t_voxel, w_voxel, n_fv, t_fv;
    double previous_seconds = -1, previous_operations = 0;   // the last classic cell run
    bool stopped = false;
    std::string rows;
    std::vector<Model> models;
    models.reserve(kMaxSteps);   // the series below points into it
    for (int n = 1; n <= kMaxSteps; ++n) {
        std::optional<Model> model = compile_bench_text(fmt::format("floz_steps_{}", n), floz_steps_text(n));
        if (!model) { ctx.failed = true; break; }
        models.push_back(std::move(*model));
    }
    std::vector<SeriesEntry> series;
    for (std::size_t i = 0; i < models.size(); ++i)
        series.push_back({fmt::format("floz_steps_{}", i + 1), &models[i], bench_grid(models[i], size)});
    std::cerr << fmt::format("bench: floz_steps_1..{} voxel {}x{}, {} interleaved rounds ...\n", models.size(), size,
                             size, voxel.repeat);
    const std::vector<BenchCell> voxel_cells = measure_interleaved(series, engine_named("voxel"), voxel);
    std::cerr << fmt::format("bench: floz_steps_1..{} fv {}x{} ...\n", models.size(), size, size);
    const std::vector<BenchCell> fv_cells = measure_interleaved(series, engine_named("fv"), fv_measure(voxel));
    for (std::size_t i = 0; i < models.size(); ++i) {
        const int n = int(i) + 1;
        const std::string& name = series[i].name;
        const Model* model = &models[i];
        const Grid& grid = series[i].grid;
        e.cells.push_back(voxel_cells[i]);
        const BenchCell& v = voxel_cells[i];
        n_voxel.push_back(n);
        t_voxel.push_back(v.cpu_median);
        w_voxel.push_back(v.median);
        BenchCell c;
        const double ops = classic_operations_per_point(model->graph, model->root);
        if (previous_seconds >= 0 && previous_seconds * ops / previous_operations > cap) stopped = true;
        if (!stopped) {
            c = run_cell(ctx, name, *model, grid, engine_named("classic"), classic);
        } else {
            c.model = name;
            c.engine = &engine_named("classic");
            c.grid = grid;
            c.operations_per_point = ops;
            c.skipped = true;
            c.skip_reason = fmt::format("over the {} per-cell cap", format_duration(cap));
            c.estimated_seconds = ctx.rate.seconds_per_operation(classic.threads) * c.total_operations();
        }
        e.cells.push_back(c);
        if (!c.skipped) {
            previous_seconds = c.median;
            previous_operations = c.operations_per_point;
            n_all_classic.push_back(n);
            t_all_classic.push_back(std::log(c.cpu_median));
            w_all_classic.push_back(std::log(c.median));
            if (c.median >= kFitMinSeconds) {
                n_classic.push_back(n);
                t_classic.push_back(std::log(c.cpu_median));
                w_classic.push_back(std::log(c.median));
            }
        }
        e.cells.push_back(fv_cells[i]);
        n_fv.push_back(n);
        t_fv.push_back(fv_cells[i].cpu_median);
        rows += fmt::format("| {} | {} | {} | {} | {} | {} |\n", n, format_operations(c.operations_per_point), time_md(c),
                            format_operations(v.operations_per_point), time_md(v), time_md(fv_cells[i]));
    }
    if (n_classic.size() < 3) { n_classic = n_all_classic; t_classic = t_all_classic; w_classic = w_all_classic; }
    const auto classic_fit = fit_line(n_classic, t_classic);
    const auto voxel_fit = fit_line(n_voxel, t_voxel);
    const auto fv_fit = fit_line(n_fv, t_fv);
    const auto classic_wall = fit_line(n_classic, w_classic);
    const auto voxel_wall = fit_line(n_voxel, w_voxel);
    const double g = classic_fit ? std::exp(classic_fit->slope) : std::nan("");
    const double g_wall = classic_wall ? std::exp(classic_wall->slope) : std::nan("");

    Plot plot;
    plot.title = fmt::format("E3: time against flozation steps ({0}x{0} grid)", size);
    plot.x_label = "flozation steps n (R0 conjunctions)";
    plot.y_label = "CPU time (s), one thread";
    plot.log_y = true;
    PlotSeries sc{"classic (median)"}, sv{"voxel (median)"}, fc{fmt::format("classic fit: x{:.2f} per step", g), true},
        fv{"voxel fit: straight line", true}, sf{"fv, P = 256 (one run)"};
    for (const BenchCell& c : e.cells) {
        const double n = std::stod(c.model.substr(c.model.rfind('_') + 1));
        if (c.skipped) continue;
        (c.engine == &engine_named("fv") ? sf : c.engine->capabilities().expanded_tree_cost ? sc : sv)
            .points.emplace_back(n, c.cpu_median);
    }
    if (classic_fit)
        for (double n : n_classic) fc.points.emplace_back(n, std::exp(classic_fit->intercept + classic_fit->slope * n));
    if (voxel_fit)
        for (double n : n_voxel) fv.points.emplace_back(n, voxel_fit->intercept + voxel_fit->slope * n);
    sc.colour = fc.colour = 0;
    sv.colour = fv.colour = 2;
    sf.colour = 1;
    plot.series = {sc, fc, sv, fv, sf};
    write_plot_svg(plot, (std::filesystem::path(out_dir) / "e3_steps.svg").string());

    e.markdown = fmt::format(
        "Generated models: the FLOZ-construction W = W & FLOZ2(...) along an open regular 24-gon, n = 1..{0}, grid "
        "{1}x{1}, one thread; the voxel cells are timed in interleaved rounds (every n once per round). Classic cells stop once the next is estimated (from the previous cell's time and the "
        "operation counts) over {2}; the rest are listed with their estimates.\n\n"
        "| n | classic ops/point | classic | voxel ops/point | voxel | fv (P = 256, one run) |\n|---|---|---|---|---|---|\n{3}\n",
        kMaxSteps, size, format_duration(cap), rows);
    e.markdown += "The fits use each cell's median **CPU time** (the process's, one thread): it measures the "
                  "engine's work, while wall time also counts waiting for a core that other jobs hold; the "
                  "wall-time fits are given beside them.\n\n";
    if (classic_fit)
        e.markdown += fmt::format(
            "- classic: time grows by a factor **{:.3f} per step** (least squares on ln(CPU time) over {} cells of "
            "≥ {} ms; R² {:.4f}; from wall time: {:.3f}, R² {:.4f}); accepted range 1.8–2.2: **{}**\n",
            g, classic_fit->points, kFitMinSeconds * 1000, classic_fit->r2, g_wall, classic_wall ? classic_wall->r2 : 0.0,
            g >= 1.8 && g <= 2.2 ? "yes" : "no");
    if (voxel_fit)
        e.markdown += fmt::format(
            "- voxel: CPU time = {} + {} per step, straight-line fit **R² {:.4f}** over {} cells (from wall time: "
            "{} per step, R² {:.4f}); required ≥ 0.98: **{}**\n",
            format_duration(std::max(0.0, voxel_fit->intercept)), format_duration(voxel_fit->slope), voxel_fit->r2,
            voxel_fit->points, voxel_wall ? format_duration(voxel_wall->slope) : "?", voxel_wall ? voxel_wall->r2 : 0.0,
            voxel_fit->r2 >= 0.98 ? "yes" : "no");
    if (fv_fit)
        e.markdown += fmt::format(
            "- fv (the papers' method, P = 256): CPU time = {} + {} per step, straight-line fit **R² {:.4f}** over {} "
            "cells, one run each\n",
            format_duration(std::max(0.0, fv_fit->intercept)), format_duration(fv_fit->slope), fv_fit->r2, fv_fit->points);
    e.markdown += "\n![E3](e3_steps.svg)\n";
    e.summary_json = fmt::format(
        "{{\"size\": [{0}, {0}], \"cell_cap_seconds\": {1}, \"classic_growth_factor\": {2}, \"classic_fit_r2\": {3}, "
        "\"classic_fit_cells\": {4}, \"voxel_seconds_per_step\": {5}, \"voxel_intercept_seconds\": {6}, "
        "\"voxel_fit_r2\": {7}, \"fitted_time\": \"cpu\", \"classic_growth_factor_wall\": {8}, "
        "\"voxel_fit_r2_wall\": {9}, \"fv_seconds_per_step\": {10}, \"fv_fit_r2\": {11}}}",
        size, json_number(cap), json_number(g), json_number(classic_fit ? classic_fit->r2 : std::nan("")),
        classic_fit ? classic_fit->points : 0, json_number(voxel_fit ? voxel_fit->slope : std::nan("")),
        json_number(voxel_fit ? voxel_fit->intercept : std::nan("")),
        json_number(voxel_fit ? voxel_fit->r2 : std::nan("")), json_number(g_wall),
        json_number(voxel_wall ? voxel_wall->r2 : std::nan("")), json_number(fv_fit ? fv_fit->slope : std::nan("")),
        json_number(fv_fit ? fv_fit->r2 : std::nan("")));
    return e;
}

Experiment e4_resolution(Context& ctx, const std::string& out_dir, const Experiment& e1) {
    Experiment e{"E4", "growth with resolution"};
    auto model = load_example(ctx, "s1_fig3a_floz.fortu");
    if (!model) {
        e.markdown = "Not run: examples/s1_fig3a_floz.fortu did not load (see the errors above).\n";
        return e;
    }
    const std::vector<int> sizes = ctx.options.quick ? std::vector<int>{50, 100, 200} : std::vector<int>{100, 200, 400, 800};
    MeasureOptions m = ctx.options.measure;
    m.budget = std::numeric_limits<double>::infinity();
    std::string rows;
    std::vector<double> pc, tc, pv, tv;
    std::vector<BenchCell> classic_cells, voxel_cells, fv_cells;
    for (int size : sizes) {
        const Grid grid = bench_grid(*model, size);
        const BenchCell* cells[2] = {nullptr, nullptr};
        const BenchCell* fv_cell = nullptr;
        for (const BenchCell& c : e1.cells)
            if (c.model == "s1_fig3a_floz.fortu" && c.engine == &engine_named("fv") && c.points() == grid.points())
                fv_cell = &c;
        fv_cells.push_back(fv_cell ? *fv_cell : run_cell(ctx, "s1_fig3a_floz.fortu", *model, grid, engine_named("fv"), fv_measure(m)));
        for (int k = 0; k < 2; ++k) {
            const Engine& engine = k == 0 ? engine_named("classic") : engine_named("voxel");
            for (const BenchCell& c : e1.cells)   // E1 measured these at its size: reuse them
                if (c.model == "s1_fig3a_floz.fortu" && c.engine == &engine && c.points() == grid.points() && !c.skipped)
                    e.cells.push_back(c), cells[k] = &e.cells.back();
            if (!cells[k]) {
                e.cells.push_back(run_cell(ctx, "s1_fig3a_floz.fortu", *model, grid, engine, m));
                cells[k] = &e.cells.back();
            }
            (k == 0 ? pc : pv).push_back(double(grid.points()));
            (k == 0 ? tc : tv).push_back(cells[k]->median);
            (k == 0 ? classic_cells : voxel_cells).push_back(*cells[k]);
        }
    }
    const PointsFit classic_fit = fit_time_per_point(classic_cells), voxel_fit = fit_time_per_point(voxel_cells);
    const PointsFit fv_points_fit = fit_time_per_point(fv_cells);
    for (const BenchCell& c : fv_cells) e.cells.push_back(c);   // after the rows' cells: e.cells[2i], [2i+1] stay theirs
    const auto& fc = classic_fit.fit;
    const auto& fv = voxel_fit.fit;
    for (std::size_t i = 0; i < sizes.size(); ++i)
        rows += fmt::format("| {0}x{0} | {1} | {2} | {3} | {4} |\n", sizes[i], format_count(std::uint64_t(pc[i])),
                            time_md(e.cells[2 * i]), time_md(e.cells[2 * i + 1]), time_md(fv_cells[i]));
    Plot plot;
    plot.title = "E4: time against resolution (S1 Fig. 3a FLOZ-construction)";
    plot.x_label = "grid points";
    plot.y_label = "wall time (s)";
    plot.log_x = plot.log_y = true;
    PlotSeries sc{"classic (median)"}, sv{"voxel (median)"}, sf{"fv, P = 256"};
    for (std::size_t i = 0; i < pc.size(); ++i) {
        if (!classic_cells[i].skipped) sc.points.emplace_back(pc[i], tc[i]);
        if (!voxel_cells[i].skipped) sv.points.emplace_back(pv[i], tv[i]);
        sf.points.emplace_back(pv[i], fv_cells[i].median);
    }
    sf.colour = 1;
    plot.series = {sc, sv, sf};
    write_plot_svg(plot, (std::filesystem::path(out_dir) / "e4_resolution.svg").string());
    e.markdown = "Model s1_fig3a_floz.fortu, the three engines (fv: the papers' method, P = 256, one run per "
                 "cell).\n\n| grid | points | classic | voxel | fv |\n|---|---|---|---|---|\n" + rows + "\n";
    e.markdown += points_fit_text("classic", classic_fit) + points_fit_text("voxel", voxel_fit) +
                  points_fit_text("fv", fv_points_fit);
    e.markdown += "\n![E4](e4_resolution.svg)\n";
    e.summary_json = fmt::format(
        "{{\"classic_seconds_per_point\": {}, \"classic_fit_r2\": {}, \"voxel_seconds_per_point\": {}, "
        "\"voxel_fit_r2\": {}, \"classic_fit_cells\": {}, \"classic_skipped_cells\": {}, \"fv_seconds_per_point\": {}, "
        "\"fv_fit_r2\": {}}}",
        json_number(fc ? fc->slope : std::nan("")), json_number(fc ? fc->r2 : std::nan("")),
        json_number(fv ? fv->slope : std::nan("")), json_number(fv ? fv->r2 : std::nan("")),
        classic_fit.cells - classic_fit.skipped, classic_fit.skipped,
        json_number(fv_points_fit.fit ? fv_points_fit.fit->slope : std::nan("")),
        json_number(fv_points_fit.fit ? fv_points_fit.fit->r2 : std::nan("")));
    return e;
}

Experiment e5_sphere(Context& ctx) {
    Experiment e{"E5", "80-triangle FLOZ3 sphere"};
    auto model = load_example(ctx, "floz3_sphere80.fortu");
    if (!model) {
        e.markdown = "Not run: examples/floz3_sphere80.fortu did not load (see the errors above).\n";
        return e;
    }
    const std::vector<int> sizes = ctx.options.quick ? std::vector<int>{32, 64} : std::vector<int>{64, 128};
    std::string rows;
    for (int size : sizes) {
        const Grid grid = bench_grid(*model, size);
        e.cells.push_back(run_cell(ctx, "floz3_sphere80.fortu", *model, grid, engine_named("voxel"), ctx.options.measure));
        e.cells.push_back(run_cell(ctx, "floz3_sphere80.fortu", *model, grid, engine_named("classic"), ctx.options.measure));
        const BenchCell& v = e.cells[e.cells.size() - 2];
        const BenchCell& c = e.cells.back();
        rows += fmt::format("| {} | {} | {} | {} | {} | {} |\n", grid_text(grid), format_count(grid.points()),
                            format_operations(v.operations_per_point), time_md(v), format_bytes(v.peak_rss_bytes),
                            time_md(c));
    }
    e.markdown = "The paper gives no timing for it.\n\n| grid | points | voxel ops/point | voxel | voxel peak memory | "
                 "classic |\n|---|---|---|---|---|---|\n" + rows;
    return e;
}

std::string paper_json(const std::vector<Experiment>& experiments, const MachineInfo& machine, const PaperOptions& o) {
    std::string out = fmt::format(
        "{{\n  \"schema\": \"fortu-bench-paper/1\",\n  \"machine\": {},\n  \"options\": {{\"quick\": {}, "
        "\"repeat\": {}, \"repeat_cap_seconds\": {}, \"threads\": {}, \"budget_operations\": {}, "
        "\"cell_cap_seconds\": {}, \"memory_method\": \"{}\"}},\n  \"experiments\": [\n",
        machine_json(machine), o.quick ? "true" : "false", o.measure.repeat, json_number(o.measure.repeat_cap),
        o.measure.threads, json_number(o.measure.budget), json_number(o.cell_cap), memory_method());
    for (std::size_t i = 0; i < experiments.size(); ++i) {
        const Experiment& e = experiments[i];
        out += fmt::format("    {{\n      \"id\": \"{}\",\n      \"title\": {},\n      \"summary\": {},\n      \"cells\": [\n",
                           e.id, json_string(e.title), e.summary_json);
        for (std::size_t k = 0; k < e.cells.size(); ++k)
            out += cell_json(e.cells[k], 8) + (k + 1 < e.cells.size() ? ",\n" : "\n");
        out += fmt::format("      ]\n    }}{}\n", i + 1 < experiments.size() ? "," : "");
    }
    return out + "  ]\n}\n";
}

}  // namespace

int run_paper_benchmarks(const PaperOptions& options) {
    std::error_code ec;
    std::filesystem::create_directories(options.out_dir, ec);
    if (ec || !std::filesystem::is_directory(options.out_dir)) {
        std::cerr << fmt::format("fortu: error: cannot create the output folder '{}': {}\n", options.out_dir,
                                 ec ? ec.message() : "not a directory");
        return 1;
    }
    Context ctx{options, examples_folder(options.examples_dir), ClassicRate{}, options.quick ? kQuickDeadline : kDeadline,
                Stopwatch{}};
    const MachineInfo machine = describe_machine();
    Stopwatch clock;
    std::vector<Experiment> experiments;
    try {
        // E3 first: its fits are the acceptance, and it should not lose to the deadline.
        Experiment e3 = e3_steps(ctx, options.out_dir);
        Experiment e1 = e1_fig3a(ctx);
        Experiment e4 = e4_resolution(ctx, options.out_dir, e1);
        Experiment e2 = e2_polygon(ctx);
        Experiment e5 = e5_sphere(ctx);
        experiments = {std::move(e1), std::move(e2), std::move(e3), std::move(e4), std::move(e5)};
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return 1;
    }
    std::string md = fmt::format(
        "# fortu bench --paper{}\n\n"
        "{}.\n\n"
        "Times are medians of up to {} runs per cell (a cell stops repeating once its runs took {}; E3's "
        "voxel cells take {}). The machine may be shared, so single runs are noisy; medians and fits are what "
        "to compare. Peak memory per cell by {}.\n",
        options.quick ? " --quick" : "", run_text(machine, options.measure.threads, clock.seconds()),
        options.measure.repeat, format_duration(options.measure.repeat_cap),
        std::max(options.measure.repeat, kVoxelStepRepeats), memory_method_text());
    for (const Experiment& e : experiments) md += fmt::format("\n## {}: {}\n\n{}", e.id, e.title, e.markdown);
    const std::filesystem::path dir(options.out_dir);
    try {
        write_file_atomically((dir / "results.md").string(), [&](OutputFile& f) { f.write(md); });
        write_file_atomically((dir / "results.json").string(),
                              [&](OutputFile& f) { f.write(paper_json(experiments, machine, options)); });
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return 1;
    }
    std::cout << md;
    std::cerr << fmt::format("bench: wrote {}/results.md, results.json, e3_steps.svg, e4_resolution.svg\n",
                             options.out_dir);
    return ctx.failed ? 1 : 0;
}

}  // namespace fortu
