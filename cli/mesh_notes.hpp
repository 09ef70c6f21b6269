// cli/mesh_notes.hpp — what a mesh leaves out that its user should know, said the same way by
// `fortu run -o m.stl` (notes) and Python's Model.mesh (warnings).
//
// Why: a mesh is closed and looks whole even where the lattice missed a part thinner than a
// cell or could not put a sharp edge back; the mesher counts both (MeshStats), and a user who
// prints or measures the mesh must hear of them without asking for --stats.
#pragma once

#include "interp/mesher.hpp"
#include "runtime/grid.hpp"

#include <string>
#include <vector>

namespace fortu {

/// One sentence per thing left out (no "note:" prefix, no newline): sharp edges more than half
/// a cell off the mesh, parts of the solid thinner than a cell missing from it. None when
/// the mesh keeps both within half a cell as far as the mesher can tell.
std::vector<std::string> mesh_notes(const MeshStats& stats, const Grid& grid);

}  // namespace fortu
