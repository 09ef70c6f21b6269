// cli/mesh_output.hpp — `fortu run MODEL -o model.stl|.obj|.ply`: the model's zero surface
// meshed on the run's grid (interp/mesher.hpp) and written by the output-format table's
// mesh rows (runtime/mesh_io.hpp), instead of grid values.
#pragma once

#include "cli/cli_options.hpp"
#include "interp/model.hpp"
#include "runtime/grid.hpp"

#include <string>

namespace fortu {

/// True when `path` names a mesh format (OutputKind::Mesh).
bool is_mesh_output(const std::string& path);

/// Meshes `model` on `grid` and writes o.output; prints a summary (or --stats). Returns the
/// exit status: 0, 1 when the file cannot be written, 2 for a 2D model.
int run_mesh_output(const Model& model, const Grid& grid, const CliOptions& o, double compile_seconds);

}  // namespace fortu
