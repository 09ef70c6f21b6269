// cli/bench/bench_paper.hpp — `fortu bench --paper`: the papers' timing experiments E1–E5
// (fv-method.md §4) end to end, written as a Markdown report, a JSON document and SVG plots.
#pragma once

#include "cli/bench/bench_measure.hpp"

#include <string>

namespace fortu {

struct PaperOptions {
    bool quick = false;             ///< smaller sizes and caps: a smoke run in well under a minute
    std::string out_dir = "bench-results";
    std::string examples_dir;       ///< where the papers' example models are; empty: found near the binary
    MeasureOptions measure;
    double cell_cap = 60.0;         ///< E3: a classic cell estimated over this many seconds is not run
};

/// Runs E1–E5, prints the Markdown report and writes it with results.json and the plots to
/// options.out_dir. Returns 0, or 1 when a model was missing or did not compile (the other
/// experiments still run).
int run_paper_benchmarks(const PaperOptions& options);

}  // namespace fortu
