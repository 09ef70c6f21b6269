// interp/mesh_cover.hpp — points of the surface the finished mesh passes more than
// kCoverDistance from become vertices of it.
//
// Why: marching tetrahedra see the solid at the lattice's nodes (and at the refined cells'
// finer ones), and the sharp-feature pass puts back the R-operations' edges; what neither
// sees is left up to a cell or two from the mesh: the tip of a blade that enters a cell
// through a face whose four corners are outside (Chainik's feet), a spike's or a wedge's tip
// whose refinement a corner's cells held back (new_Chainik's base rim), a twisted edge
// (Tor1). This pass looks for them as the tests' independent check does: it projects points
// onto the surface by Newton, from a half-cell lattice in the cells round the mesh's bent
// parts, and measures each projection's distance to the mesh. A projection farther than
// kCoverDistance is put in as a vertex, splitting a triangle near it into three where they
// are not degenerate, cross no other and keep within kCoverDistance of the surface. A split
// keeps every edge in two triangles and every winding, so the mesh stays closed, manifold and
// oriented, and it adds a vertex and moves none, so the sharp features stay exact.
#pragma once

#include "interp/engine.hpp"
#include "interp/ir/ir.hpp"
#include "runtime/grid.hpp"
#include "runtime/mesh.hpp"

#include <array>
#include <cstddef>
#include <vector>

namespace fortu {

/// How far from the mesh, in cells, a surface point may be before it is put in: under the
/// half cell the mesh is held to, so that points between the probes are within it too (at
/// 0.4, new_Chainik at 24 nodes kept a surface point 0.50 cells off, 0.13 cells from a probe's
/// landing point found 0.61 off; at 0.3, at 64 nodes, one 0.504 off, 0.458 now).
inline constexpr double kCoverDistance = 0.25;

/// What cover_surface did (for --stats).
struct CoverStats {
    std::size_t probes = 0;     ///< points projected onto the surface
    std::size_t far = 0;        ///< projections farther than kCoverDistance from the mesh
    std::size_t inserted = 0;   ///< of those, put in as vertices
    std::size_t covered = 0;    ///< of those, covered by another's vertex (when its turn came, or at the end)
    std::size_t refused = 0;    ///< of those, no split of a triangle near them was valid, and still far at the end
    double farthest_left = 0;   ///< the farthest refused at the end, in cells
    /// Of the sharp edges' crossings that are not vertices (sharpen_features' crossings_left),
    /// those more than a billionth of a cell from the finished mesh, and the farthest, in
    /// cells (infinity: no triangle within a cell): there the marching-tetrahedra surface cuts
    /// the edge (a wedge thinner than a cell whose cells could not be redone).
    std::size_t crossings_off_mesh = 0;
    double farthest_crossing_off = 0;
};

/// Puts into `mesh` (made on `grid`'s lattice, vertex normals outward) a vertex at each
/// surface point it finds more than kCoverDistance from it, and at each of `edge_points`
/// (points of the surface: the sharp edges' crossings the feature pass left off) as far. The
/// result depends on the input only, not on the number of threads.
void cover_surface(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh, const EvalOptions& options,
                   const std::vector<std::array<double, 3>>& edge_points = {}, CoverStats* stats = nullptr);

}  // namespace fortu
