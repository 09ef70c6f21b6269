// cli/run_checks.hpp — what `fortu run` checks before it evaluates anything, so that a run
// never ends in a partial result: every output's folder exists and is writable, no two
// outputs name the same file (`-o m_1.png --mimages m_%d.png`), and the grid, its outputs
// and the writers' buffers fit in the memory available (`--force` runs anyway).
#pragma once

#include "cli/cli_options.hpp"
#include "runtime/grid.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace fortu {

/// One file a run will write and the option that asked for it.
struct PlannedFile {
    std::string option;   ///< "-o", "--mimages", "--contour"
    std::string path;
};

/// Every file the run's outputs write on `grid`, series expanded (slice_%d.png, m_%d.png).
std::vector<PlannedFile> planned_files(const CliOptions& o, const Grid& grid);

/// Throws UsageError for two outputs writing one file or an unusable --mimages name, and
/// OutputError (`cannot write 'PATH': directory 'D' does not exist`) for a folder that
/// cannot take the file.
void check_outputs(const CliOptions& o, const Grid& grid);

/// Bytes the run needs at its peak: the field, the engine's per-point buffers and the largest
/// writer's buffers. An estimate, on the high side.
std::size_t estimated_run_bytes(const CliOptions& o, const Grid& grid);

/// MemAvailable of /proc/meminfo in bytes; 0 when unknown.
std::size_t available_memory();

/// Throws UsageError when estimated_run_bytes() exceeds `available` (MemAvailable by
/// default) unless --force.
void check_memory(const CliOptions& o, const Grid& grid, std::size_t available = 0);

}  // namespace fortu
