// interp/mesh_features.hpp — sharp edges and corners put back into a marching-tetrahedra
// mesh (the mesher's last pass, interp/mesher.cpp).
//
// Why: an R-function solid's edges are exactly where both operands of one R-operation vanish,
// and its corners where two such edges meet; marching tetrahedra keep vertices on grid edges
// and so cut them off by up to a cell. In each grid cell whose surface normals disagree, the
// pass finds the R-operation whose operands both vanish in the cell and solves for the
// feature point there with the `fortu singular` machinery: Newton's method on (φ, ψ) = 0 with
// exact gradients (the minimum-norm step onto the edge), or on three independent operands for
// a corner. The cell's patch of triangles (a disc; its boundary lies on the cell's faces and is
// shared with the neighbours) is replaced by a fan from that point over the same boundary
// (Kobbelt et al.'s extended marching cubes). Then, across each face between two such cells,
// the fan triangles on the face's piece of boundary are flipped into the edge joining the two
// feature points, so the mesh has edges along the feature, not only vertices on it.
// Every change keeps the boundary a neighbour sees, so watertightness, manifoldness and
// orientation stay as the mesher made them; each change is kept only when the new triangles,
// projected along the feature's mean outward normal, all keep their orientation and wind once
// around each feature point (the patch is then a graph over that plane, so it cannot fold or
// cross itself), are not degenerate, and the feature point lies in its cell (so the patch
// meets other cells' triangles only on the shared boundary). A cell that fails any test keeps
// its marching-tetrahedra patch.
#pragma once

#include "interp/ir/ir.hpp"
#include "runtime/grid.hpp"
#include "runtime/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fortu {

struct FeatureStats {
    std::size_t cells_tested = 0;     ///< cells whose normals disagree
    std::size_t edge_vertices = 0;    ///< feature vertices on an R-operation's edge curve
    std::size_t corner_vertices = 0;  ///< feature vertices where edges meet
    std::size_t joined_faces = 0;     ///< faces across which two feature vertices were joined
};

/// Rewrites `mesh` (made on `grid`'s lattice; `triangle_cells[t]` the cell of triangle t,
/// x + cells_x·(y + cells_y·z)) with vertices on the sharp features of `root`'s R-operations.
/// Unused vertices are dropped; the order of the result depends on the input only.
void sharpen_features(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh,
                      const std::vector<uint64_t>& triangle_cells, FeatureStats* stats = nullptr);

}  // namespace fortu
