// cli/bench/bench_performance.hpp — `fortu bench --performance`: issue 5's performance suite
// (prospero.vm, the 64-segment FLOZ contour, the S1 Fig. 3a FLOZ contour with its M-images)
// in one command, each row beside its target and the reference figures.
#pragma once

#include "cli/bench/bench_measure.hpp"

#include <string>

namespace fortu {

struct PerformanceOptions {
    bool quick = false;                        ///< small grids: a smoke run, not comparable with the targets
    std::string out_dir = "bench-results/perf";
    std::string data_dir;       ///< the folder with prospero.vm; empty: shared_data_dir() (data_paths.hpp)
    std::string examples_dir;   ///< where s1_fig3a_floz.fortu is; empty: examples_dir() (data_paths.hpp)
    MeasureOptions measure;     ///< repeat: the median is over this many runs
};

/// The folder prospero.vm is looked for in: `given`, else $FORTU_SHARED_DIR/data (as the
/// golden tests use it), else the shared data folder configured at build time (data_paths.hpp).
std::string shared_data_folder(const std::string& given);

/// Runs the suite, prints the Markdown table and writes results.md and results.json to
/// options.out_dir. Returns 0, or 1 when a model was missing or did not compile (its rows
/// say "Not run"; the others still run) or the results could not be written.
int run_performance_benchmarks(const PerformanceOptions& options);

}  // namespace fortu
