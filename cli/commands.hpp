// cli/commands.hpp — the products of the `fortu` binary that are libraries of their own
// (cli/golden/, cli/bench/, cli/repl/). Each takes the arguments after its name and returns
// the exit status (0 success, 1 model error or failed check, 2 usage error; a UsageError
// thrown out of it is printed by main as `fortu: error: ...` with status 2).
#pragma once

#include <string>
#include <vector>

namespace fortu {

/// `fortu golden DIR|FILE... [--engine both|classic|voxel] [--update] [--jobs N]` (golden/golden.cpp)
int run_golden_command(const std::vector<std::string>& args);

/// `fortu bench MODEL... [--engines ...] [--sizes ...] [--repeat N] [--json F] [--csv F] [--plot F]`
/// and `fortu bench --paper` (bench/bench.cpp)
int run_bench_command(const std::vector<std::string>& args);

/// `fortu repl [MODEL.fortu]` (repl/repl.cpp)
int run_repl_command(const std::vector<std::string>& args);

}  // namespace fortu
