// cli/bench/bench_measure.hpp — `fortu bench`'s measuring: loading models (from .fortu/.vm files or
// generated text), the grid of a size, and one cell (model × engine × grid) timed over repeats
// with its cost per point and peak memory, optionally with the M-images computed after each
// evaluation. Over-budget classic cells are kept, marked skipped, with their estimated time,
// so a table never silently drops the slow side of a comparison.
#pragma once

#include "cli/model_setup.hpp"
#include "interp/engine.hpp"
#include "interp/model.hpp"
#include "runtime/grid.hpp"
#include "runtime/resources.hpp"

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// The example models: `given` if not empty, else examples_dir() (cli/data_paths.hpp).
std::filesystem::path examples_folder(const std::string& given);

/// Reads and compiles a model file (.fortu, or a .vm model imported); diagnostics go to
/// stderr. nullopt on any error.
std::optional<Model> load_bench_model(const std::string& path);

/// Compiles generated FORTU text (E3's polygons); nullopt (and diagnostics on stderr) on error.
std::optional<Model> compile_bench_text(const std::string& name, const std::string& text);

/// E3's generated model: the FLOZ-construction W = W & FLOZ2(...) of the first `steps` + 1
/// edges of a regular 24-gon of radius 0.8 (an open polyline for steps ≤ 22): `steps` R-conjunctions.
std::string floz_steps_text(int steps);

/// The model's domain sampled with `nodes` nodes per axis (N×N, or N×N×N for 3 arguments).
Grid bench_grid(const Model& model, int nodes);

struct MeasureOptions {
    int repeat = 3;               ///< timed runs per cell (at least one)
    double repeat_cap = 20.0;     ///< no further repeat once the runs so far took this long (s)
    int threads = 0;              ///< EvalOptions::threads
    double budget = 2e10;         ///< classic operations per cell before it is skipped
    bool mimages = false;         ///< each run also computes the M-images (not for sign cells)
};

/// One measured (or skipped) combination of model, engine and grid.
struct BenchCell {
    std::string model;                 ///< path or generated name
    std::string label;                 ///< the short name tables and plots show ("" = model)
    const Engine* engine = &default_engine();   ///< what the cell times (its name goes in JSON and CSV)
    Grid grid;
    double operations_per_point = 0;   ///< classic: expanded tree; others: tape instructions
    bool skipped = false;
    std::string skip_reason;           ///< why, with the operation count
    std::vector<double> seconds;       ///< each timed run, in order
    double min = 0, median = 0, max = 0;
    std::vector<double> cpu_seconds;   ///< the process's CPU time of each run: the work itself,
                                       ///< unaffected by waiting for a core on a shared machine
    double cpu_median = 0;
    int mimages = 0;                   ///< M-images computed in each run (4 in 2D, 5 in 3D; 0: none)
    std::vector<double> mimages_seconds;   ///< the M-images' part of each run (in `seconds` too)
    double mimages_median = 0;
    std::size_t peak_rss_bytes = 0;    ///< the process's peak RSS during the cell
    std::size_t rss_growth_bytes = 0;  ///< that peak minus the RSS when the cell started
    double estimated_seconds = -1;     ///< skipped classic cells: operations × measured rate; < 0 unknown

    std::size_t points() const { return grid.points(); }
    const std::string& shown_name() const { return label.empty() ? model : label; }
    double total_operations() const { return operations_per_point * double(points()); }
    double seconds_per_point() const { return points() ? median / double(points()) : 0.0; }
};

/// How the classic engine's speed is known for estimates, per thread count: the rate (seconds
/// per operation) of the most expensive classic cell measured so far with that many threads,
/// else a short calibration run.
class ClassicRate {
public:
    void observe(const BenchCell& cell, int threads);
    /// Seconds per classic operation (runs the calibration the first time if nothing was observed).
    double seconds_per_operation(int threads);

private:
    struct Known {
        double seconds_per_operation = -1;
        double operations = 0;   ///< of the cell it was measured on (0: calibration)
    };
    std::map<int, Known> known_;
};

/// A cell not yet measured: its name, grid, engine and operations per point (what a table's
/// layout and an estimate need).
BenchCell plan_cell(const std::string& name, const Model& model, const Grid& grid, const Engine& engine);

/// Times `engine` on `model` over `grid`: repeats (stopping early after options.repeat_cap
/// seconds), min/median/max, peak memory; with options.mimages each run is the evaluation
/// plus the FV model's normalised components (FvModel), i.e. the M-images before palette
/// encoding and file writing. A classic cell over options.budget, or nested deeper than the
/// classic engine recurses, is returned skipped with its estimate.
BenchCell measure_cell(const std::string& name, const Model& model, const Grid& grid, const Engine& engine,
                       const MeasureOptions& options, ClassicRate& rate);

/// One (name, model, grid) of an interleaved series.
struct SeriesEntry {
    std::string name;
    const Model* model = nullptr;
    Grid grid;
};

/// Times `engine` on every entry, options.repeat rounds, each round one run of every entry in
/// turn: a change in the machine's load during the series then shifts every entry alike
/// instead of bending the curve (E3's voxel line). Peak memory is the series' own, the same
/// for every cell.
std::vector<BenchCell> measure_interleaved(const std::vector<SeriesEntry>& entries, const Engine& engine,
                                           const MeasureOptions& options);

double median_of(std::vector<double> values);

}  // namespace fortu
