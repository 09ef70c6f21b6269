// cli/run_feedback.hpp — what a successful `fortu run` says on standard error: one line per
// file written, `wrote x.png (512x512)`, as the REPL does (silenced by --quiet).
//
// Why: a run that prints nothing leaves the user guessing where the picture went and how big
// it is, and a %d series or --mimages writes several files whose names the user did not type.
#pragma once

#include "cli/cli_options.hpp"
#include "runtime/grid.hpp"

#include <string>

namespace fortu {

/// `wrote FILE (SIZE)` for each file the run's outputs wrote on `grid` (planned_files), SIZE
/// being the picture's WxH for pictures, contours and series members, the grid's WxH[xD] for
/// values and volumes; `<stdout>` for `-o -`. "" with --quiet.
std::string written_lines(const CliOptions& o, const Grid& grid);

/// `wrote FILE (WxH)` for one picture (a 3D model's shaded view); "" with --quiet.
std::string written_picture_line(const CliOptions& o, const std::string& path, int width, int height);

}  // namespace fortu
