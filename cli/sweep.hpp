// cli/sweep.hpp — `fortu run MODEL --set R=0.1:1.0:0.1 -o out_%R.png`: one run per value of a
// CONSTANT (CompileOptions::constants), each point's files named by substituting %NAME,
// spread over the ranks of an mpirun job (a shared counter) or run one after another, each
// on all threads.
#pragma once

#include "cli/cli_options.hpp"

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

/// Runs `run_one` for every point of the product of o.sets (each with constants and output
/// names set, sets cleared); returns the worst exit status. Throws UsageError when a
/// sweep's outputs would overwrite each other (no %NAME for an axis of several values).
int run_sweep(const CliOptions& o, const std::function<int(const CliOptions&)>& run_one);

}  // namespace fortu
