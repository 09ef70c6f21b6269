// cli/fv_options.hpp — the options of `fortu run` that belong to the fv engine (--palette,
// --steps) and --compare, and the checks across them and --engine.
#pragma once

#include "cli/cli_options.hpp"
#include "cli/option_table.hpp"

namespace fortu {

/// Adds --palette, --steps and --compare to a grid command's table.
void add_fv_options(OptionTable& t, CliOptions& o);

/// Once every option is applied: --palette and --steps need an engine that has them
/// (EngineCapabilities::palette, ::steps), --compare one that computes values. Throws UsageError.
void check_fv_options(const CliOptions& o);

}  // namespace fortu
