// cli/bench/bench_performance.cpp — issue 5's suite. Why a fixed suite: the targets and the peers'
// reference figures are for particular models, grids and kinds of work (a sign image, a full
// field in float32 or float64, a field with its M-images), so one command measures exactly
// those and prints them beside each other. Every cell is an ordinary bench cell
// (measure_cell), so the numbers mean what `fortu bench MODEL --engines ...` means.
#include "cli/bench/bench_performance.hpp"

#include "cli/data_paths.hpp"

#include "cli/bench/bench_report.hpp"
#include "interp/vector_math.hpp"
#include "interp/tape_jit.hpp"
#include "interp/voxel_engine.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/output_error.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <fmt/format.h>
#include <iostream>

namespace fortu {
namespace {

namespace fs = std::filesystem;

constexpr double kMiB = 1024.0 * 1024.0;

enum class SuiteModel { Prospero, Floz64, Fig3a, Bear, Tanglecube };

/// One row of the table: a model at a size, timed one way.
struct Work {
    SuiteModel model;
    const char* what;            ///< after the model and the grid: "sign image", ...
    int size, quick_size;        ///< nodes per axis
    const char* engine;          ///< its name in the engine table
    bool mimages;                ///< evaluation plus the four M-images
    bool show_peak;              ///< peak memory printed beside the time
    double target_seconds;       ///< 0: no target
    double target_peak_mib;      ///< 0: no target
    const char* target;
    const char* reference;       ///< issue 5's reference figures, measured on this kind of machine
};

constexpr const char* kNone = "—";

constexpr Work kSuite[] = {
    {SuiteModel::Prospero, "sign image", 1024, 128, "sign", false, false, 0.011, 0, "≤ 11 ms",
     "libfive interval 34 ms"},
    {SuiteModel::Prospero, "full field, float32", 1024, 128, "voxel-f32", false, true, 0.170, 64,
     "≤ 170 ms, peak ≤ 64 MiB", "libfive brute force 513 ms, numpy float32 1715 ms / 71 MiB, OpenVDB AX 589 ms"},
    {SuiteModel::Prospero, "full field, float64", 1024, 128, "voxel", false, true, 0, 0, kNone, kNone},
    {SuiteModel::Floz64, "full field, float32", 800, 100, "voxel-f32", false, false, 0.020, 0,
     "≤ 20 ms", "numpy 287 ms, OpenVDB AX 145 ms, libfive 62 ms"},
    {SuiteModel::Floz64, "full field, float64", 800, 100, "voxel", false, false, 0, 0, kNone, kNone},
    {SuiteModel::Floz64, "sign image", 800, 100, "sign", false, false, 0, 0, kNone,
     "libfive interval 382 ms"},
    {SuiteModel::Fig3a, "field and its four M-images, float32", 800, 100, "voxel-f32", true, false,
     0.020, 0, "≤ 20 ms", kNone},
    {SuiteModel::Fig3a, "field and its four M-images, float64", 800, 100, "voxel", true, false, 0.020, 0,
     "≤ 20 ms", kNone},
    // 3D (issue 13's figures: one thread, libfive at commit e8370983 built with its own flags).
    {SuiteModel::Bear, "full field, float32", 128, 32, "voxel-f32", false, true, 0, 0, kNone,
     "libfive brute force 147 ms (1 thread)"},
    {SuiteModel::Bear, "full field, float32", 256, 32, "voxel-f32", false, true, 0, 0, kNone,
     "libfive brute force 1155 ms (1 thread)"},
    {SuiteModel::Bear, "sign volume", 128, 32, "sign", false, true, 0, 0, kNone, kNone},
    {SuiteModel::Bear, "sign volume", 256, 32, "sign", false, true, 0, 0, kNone, "libfive octree 757 ms (1 thread)"},
    {SuiteModel::Tanglecube, "full field, float32", 128, 32, "voxel-f32", false, true, 0, 0, kNone, kNone},
    {SuiteModel::Tanglecube, "full field, float32", 256, 32, "voxel-f32", false, true, 0, 0, kNone, kNone},
    {SuiteModel::Tanglecube, "sign volume", 128, 32, "sign", false, true, 0, 0, kNone, kNone},
    {SuiteModel::Tanglecube, "sign volume", 256, 32, "sign", false, true, 0, 0, kNone,
     "libfive octree 7 ms (1 thread)"},
};

/// A model of the suite: where it is, what it is called in the table, and the loaded model
/// or why it is not there.
struct LoadedModel {
    std::string label;
    fs::path path;
    std::optional<Model> model;
    std::string problem;   ///< set when `model` is empty
};

LoadedModel load_suite_model(const std::string& label, const fs::path& path, const std::string& hint) {
    LoadedModel m{label, path, std::nullopt, ""};
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        m.problem = fmt::format("{} not found in {}", path.filename().string(), path.parent_path().string());
        std::cerr << fmt::format("fortu: error: {}; {}\n", m.problem, hint);
        return m;
    }
    m.model = load_bench_model(path.string());
    if (!m.model) m.problem = fmt::format("{} did not compile (see the errors above)", path.string());
    return m;
}

/// A row's outcome: its cell when it ran, else why not.
struct RowResult {
    const Work* work;
    std::string label;   ///< the table's "work" cell
    const LoadedModel* model;
    int size;
    std::optional<BenchCell> cell;

    bool time_met() const { return cell && cell->median <= work->target_seconds; }
    bool peak_met() const {
        return cell && (work->target_peak_mib <= 0 || double(cell->peak_rss_bytes) <= work->target_peak_mib * kMiB);
    }
    bool met() const { return work->target_seconds > 0 && time_met() && peak_met(); }
};

std::string fortu_text(const RowResult& r) {
    if (!r.cell) return fmt::format("Not run: {}", r.model->problem);
    const BenchCell& c = *r.cell;
    std::string text = format_duration(c.median);
    if (c.mimages) text += fmt::format(" (M-images {})", format_duration(c.mimages_median));
    if (r.work->show_peak)
        text += fmt::format(", peak {} (+{})", format_bytes(c.peak_rss_bytes), format_bytes(c.rss_growth_bytes));
    return text;
}

std::string target_text(const RowResult& r, bool quick) {
    const Work& w = *r.work;
    if (w.target_seconds <= 0 || !r.cell) return w.target;
    if (quick) return fmt::format("{} (not comparable: --quick)", w.target);
    if (w.target_peak_mib <= 0) return fmt::format("{}: {}", w.target, r.met() ? "met" : "**missed**");
    return fmt::format("{}: time {}, peak {}", w.target, r.time_met() ? "met" : "**missed**",
                       r.peak_met() ? "met" : "**missed**");
}

std::string rows_markdown(const std::vector<RowResult>& rows, bool quick) {
    std::string md = "| work | fortu (median) | target | reference (measured on this kind of machine) |\n|---|---|---|---|\n";
    for (const RowResult& r : rows)
        md += fmt::format("| {} | {} | {} | {} |\n", r.label, fortu_text(r), target_text(r, quick), r.work->reference);
    return md;
}

std::string rows_json(const std::vector<RowResult>& rows, bool quick) {
    std::string out;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const RowResult& r = rows[i];
        const Work& w = *r.work;
        const bool judged = r.cell && w.target_seconds > 0 && !quick;
        out += fmt::format(
            "    {{\n      \"work\": {},\n      \"model\": {},\n      \"engine\": \"{}\",\n      \"size\": [{}, {}],\n"
            "      \"mimages\": {},\n      \"target_seconds\": {},\n      \"target_peak_rss_bytes\": {},\n"
            "      \"reference\": {},\n      \"status\": \"{}\",\n      \"met\": {},\n      \"reason\": {},\n"
            "      \"cell\": {}\n    }}{}\n",
            json_string(r.label), json_string(r.model->path.string()), w.engine, r.size, r.size,
            w.mimages ? "true" : "false", w.target_seconds > 0 ? json_number(w.target_seconds) : "null",
            w.target_peak_mib > 0 ? json_number(w.target_peak_mib * kMiB) : "null", w.reference == kNone ? "null" : json_string(w.reference),
            r.cell ? "measured" : "not run", judged ? (r.met() ? "true" : "false") : "null",
            r.cell ? "null" : json_string(r.model->problem), r.cell ? cell_json(*r.cell, 6).substr(6) : "null",
            i + 1 < rows.size() ? "," : "");
    }
    return out;
}

/// The 1-minute load average, which says how shared the machine was ("?" if unknown).
std::string load_average() {
    std::ifstream in("/proc/loadavg");
    std::string first;
    return in >> first ? first : "?";
}

}  // namespace

std::string shared_data_folder(const std::string& given) {
    if (!given.empty()) return given;
    return shared_data_dir().string();
}

int run_performance_benchmarks(const PerformanceOptions& options) {
    std::error_code ec;
    fs::create_directories(options.out_dir, ec);
    if (ec || !fs::is_directory(options.out_dir)) {
        std::cerr << fmt::format("fortu: error: cannot create the output folder '{}': {}\n", options.out_dir,
                                 ec ? ec.message() : "not a directory");
        return 1;
    }
    const std::string load = load_average();
    Stopwatch clock;
    const std::string data = shared_data_folder(options.data_dir);
    const fs::path floz64 = bench_models_dir() / "floz64.vm";
    const LoadedModel models[] = {
        load_suite_model("prospero.vm", fs::path(data) / "prospero.vm",
                         "give --data DIR, the folder with prospero.vm, or set FORTU_SHARED_DIR"),
        load_suite_model("64-segment FLOZ (floz64.vm)", floz64, "set FORTU_BENCH_MODELS to the source tree's bench/models"),
        load_suite_model("S1 Fig. 3a FLOZ contour", examples_folder(options.examples_dir) / "s1_fig3a_floz.fortu",
                         "give --examples DIR"),
        load_suite_model("bear.vm", fs::path(data) / "bear.vm", "give --data DIR, the folder with bear.vm"),
        load_suite_model("tanglecube.vm", fs::path(data) / "tanglecube.vm", "give --data DIR, the folder with tanglecube.vm"),
    };
    const MachineInfo machine = describe_machine();
    ClassicRate unused_rate;   // the suite has no classic cell
    std::vector<RowResult> rows;
    for (const Work& w : kSuite) {
        const LoadedModel& m = models[int(w.model)];
        const int size = options.quick ? w.quick_size : w.size;
        const bool solid = w.model == SuiteModel::Bear || w.model == SuiteModel::Tanglecube;
        RowResult r{&w, fmt::format("{} {}{} {}", m.label, size, solid ? "³" : "²", w.what), &m, size, std::nullopt};
        if (m.model) {
            MeasureOptions measure = options.measure;
            measure.mimages = w.mimages;
            const Grid grid = bench_grid(*m.model, size);
            std::cerr << fmt::format("bench: {} {} {}{} ...\n", m.path.filename().string(), w.engine,
                                     grid_text(grid), w.mimages ? " + M-images" : "");
            r.cell = measure_cell(m.path.string(), *m.model, grid, engine_named(w.engine), measure, unused_rate);
        }
        rows.push_back(std::move(r));
    }
    const bool all_ran = std::all_of(rows.begin(), rows.end(), [](const RowResult& r) { return r.cell.has_value(); });

    std::string md = fmt::format(
        "# fortu bench --performance{}\n\n"
        "{}; load average {} before it. Instruction sets: lane loops {}, compiled tapes {}, float32 transcendentals {} ({}).\n\n"
        "Each time is the median of {} runs of the evaluation alone, as `fortu run` makes it (no file writing): "
        "`--sign-only`'s interval-pruned renderer for a sign image, the voxel engine for a full field "
        "(`--precision float32` or float64); the M-image rows add the FV model's normalised components n1..n4 "
        "(what `--mimages` encodes and writes). Peak memory: the process's peak RSS during the cell (+ what the "
        "cell added), by {}. Models: prospero.vm from {}; floz64.vm = `/usr/bin/python3 ../shared/peers/gen_floz.py "
        "floz64.vm --k 64`, committed as bench/models/floz64.vm; examples/s1_fig3a_floz.fortu; bear.vm and tanglecube.vm "
        "from the same folder as prospero.vm (the 3D sign rows go through the engine table, so they keep a float64 "
        "field; `fortu run --sign-only` keeps 3D signs as int8).{}\n\n",
        options.quick ? " --quick" : "", run_text(machine, options.measure.threads, clock.seconds()), load,
        lane_loop_isa(), tape_jit_available() ? jit_width_name(tape_jit_width()) : "none", vector_math::isa_name(vector_math::active_isa()), vector_math::libraries_text(),
        options.measure.repeat, memory_method_text(), data,
        options.quick ? " --quick: small grids, not comparable with the targets." : "");
    md += rows_markdown(rows, options.quick);
    const std::string json = fmt::format(
        "{{\n  \"schema\": \"fortu-bench-performance/1\",\n  \"machine\": {},\n  \"options\": {{\"quick\": {}, "
        "\"repeat\": {}, \"repeat_cap_seconds\": {}, \"threads\": {}, \"memory_method\": \"{}\", \"data_dir\": {}}},\n"
        "  \"rows\": [\n{}  ]\n}}\n",
        machine_json(machine), options.quick ? "true" : "false", options.measure.repeat,
        json_number(options.measure.repeat_cap), options.measure.threads, memory_method(), json_string(data),
        rows_json(rows, options.quick));
    const fs::path dir(options.out_dir);
    try {
        write_file_atomically((dir / "results.md").string(), [&](OutputFile& f) { f.write(md); });
        write_file_atomically((dir / "results.json").string(), [&](OutputFile& f) { f.write(json); });
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return 1;
    }
    std::cout << md;
    std::cerr << fmt::format("bench: wrote {}/results.md, results.json\n", options.out_dir);
    return all_ran ? 0 : 1;
}

}  // namespace fortu
