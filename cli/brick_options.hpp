// cli/brick_options.hpp — the options of bricked runs (--memory, --resume, --brick) and of sweeps (--set): a 3D run
// to .vti/.vdb cut into bricks (brick_run.hpp).
#pragma once

#include "cli/cli_options.hpp"
#include "cli/option_table.hpp"

#include <cstddef>
#include <string>

namespace fortu {

/// Adds --memory, --resume, --brick and --set (sweep.hpp) to run's table.
void add_brick_options(OptionTable& t, CliOptions& o);

/// "2G", "512M", "64K", "1000000" as bytes; throws UsageError naming `what`.
std::size_t parse_memory_size(const std::string& text, const std::string& what);

}  // namespace fortu
