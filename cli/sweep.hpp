// cli/sweep.hpp — `fortu run MODEL --set R=0.1:1.0:0.1 -o out_%R.png`: one run per value of a
// CONSTANT (CompileOptions::constants), each point's files named by substituting %NAME,
// spread over the ranks of an mpirun job (a counter they share, given by the caller so this
// file needs no MPI), or on one process run side by side on its threads (the first alone,
// to measure what one run needs).
#pragma once

#include "cli/cli_options.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace fortu {

/// One --set: a CONSTANT's name and its values (NAME=V, or NAME=FIRST:LAST:STEP with LAST
/// included when the steps reach it within rounding). Throws UsageError.
struct SweepAxis {
    std::string name;
    std::vector<double> values;
};
SweepAxis parse_sweep(const std::string& text);

/// `path` with every %NAME replaced by its value (shortest text that reads back the same).
std::string sweep_path(const std::string& path, const std::vector<std::pair<std::string, double>>& point);

/// Draws the next point number, 0, 1, 2, ... once across every process of the job.
using SweepCounter = std::function<std::uint64_t()>;

/// Runs `run_one` for every point of the product of o.sets (each with constants and output
/// names set, sets cleared); returns the worst exit status. With `shared_next` (an mpirun
/// job) this process runs, one after another, the points it draws. Without, the runs after
/// the first go side by side, so `run_one` must be safe to call from several threads at
/// once. Throws UsageError when a sweep's outputs would overwrite each other (no %NAME for
/// an axis of several values).
int run_sweep(const CliOptions& o, const std::function<int(const CliOptions&)>& run_one,
              const SweepCounter& shared_next = {});

}  // namespace fortu
