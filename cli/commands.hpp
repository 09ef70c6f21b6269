// cli/commands.hpp — the commands of the `fortu` binary that have their own file. Each takes
// the arguments after its name and returns the exit status (0 success, 1 model error or
// failed check, 2 usage error).
#pragma once

#include <string>
#include <vector>

namespace fortu {

/// `fortu golden DIR|FILE... [--engine both|classic|voxel] [--update] [--jobs N]` (golden.cpp)
int run_golden_command(const std::vector<std::string>& args);

/// `fortu bench MODEL... [--engines ...] [--sizes ...] [--repeat N] [--json F] [--csv F] [--plot F]`
/// and `fortu bench --paper` (bench.cpp)
int run_bench_command(const std::vector<std::string>& args);

/// `fortu repl [MODEL.fortu]` (repl.cpp)
int run_repl_command(const std::vector<std::string>& args);

}  // namespace fortu
