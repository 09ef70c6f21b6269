// cli/run_feedback.hpp — what a successful `fortu run` says on standard error: one line per
// file written, `wrote x.png (512x512)`, as the REPL does (silenced by --quiet).
//
// Why: a run that prints nothing leaves the user guessing where the picture went and how big
// it is, and a %d series or --mimages writes several files whose names the user did not type.
#pragma once

#include "cli/cli_options.hpp"
#include "runtime/grid.hpp"

#include <string>
#include <vector>

namespace fortu {

/// `wrote FILE (SIZE)` for each file the run's outputs wrote on `grid` (planned_files), SIZE
/// being the picture's WxH for pictures, contours and series members, the grid's WxH[xD] for
/// values and volumes; `<stdout>` for `-o -`. "" with --quiet.
std::string written_lines(const CliOptions& o, const Grid& grid);

/// `wrote N step files (WxH) into DIR: FIRST ... LAST` for `--steps DIR` (files in the order
/// written, a picture of one plane each); one line, as a step series can be dozens of files.
/// "" with --quiet or no files.
std::string written_steps_line(const CliOptions& o, const Grid& grid, const std::vector<std::string>& files);

/// `wrote FILE (WxH)` for one picture (a 3D model's shaded view); "" with --quiet.
std::string written_picture_line(const CliOptions& o, const std::string& path, int width, int height);

}  // namespace fortu
