// interp/mesher.hpp — the zero surface of a 3D model as a closed triangle mesh (`fortu run
// -o model.stl|.obj|.ply`).
//
// Why marching tetrahedra on the Kuhn split, with vertices found on the edges: it is the one
// scheme here whose guarantees hold by construction, with no repair pass and no case the
// code must get lucky on. Every cube of the grid is cut into the same six tetrahedra around
// its main diagonal, so neighbouring cubes cut their shared faces the same way (a consistent
// triangulation of space). In each tetrahedron the surface is one triangle or one quad (two
// triangles) whose vertices lie strictly inside the edges whose ends differ in sign, so:
// - watertight and manifold: a triangle edge lies on a tetrahedron face and is shared by
//   exactly the two tetrahedra of that face, whose sign pattern on it is the same;
// - no self-intersections: a tetrahedron's triangles lie inside it and meet its faces only
//   in the segment between the face's two crossing points, which the neighbour shares;
// - no degenerate triangles: each vertex is kept at least kEdgeMargin of its edge from the
//   nodes, so three vertices are never collinear (they lie on three different edges);
// - oriented outward: the orientation of each case comes from the tetrahedron's geometry,
//   a table computed once (the side of the triangle's plane the inside nodes lie on never
//   changes as vertices move along their edges).
// Each vertex is the true zero of the field on its edge, to round-off: Newton's method along
// the edge with the exact gradient (dual numbers), safeguarded by bisection; its normal is the
// exact gradient at the last iterate (within 1e-7 of an edge of it). Dual contouring places
// vertices inside cells and so can sit on sharp corners, but its manifold and
// intersection-free variants need repair passes and extra vertices; we chose the guarantees,
// then put the sharp edges and corners back cell by cell with a pass that keeps them
// (mesh_features.hpp: the R-operations' edge curves traced cell to cell, chains of mesh edges).
//
// Only cells the surface can cross are evaluated: an octree over leaves of 8³ cells, each box
// tested with interval arithmetic (interval.hpp) and its tape shortened for the box
// (box_simplify.hpp, keeping values exact), as the sign renderer does for pictures. Memory and
// time grow with the surface's area, not the grid's volume. A solid that the domain cuts is
// closed on the domain's outer nodes, which count as outside. A node where the formula is 0/0
// (ARCTAN(Y/X) on the Z axis) takes the field beside it, not NaN's "outside", and a zero the
// solid only touches from inside (two parts joined on a plane) counts as inside: a node line
// or plane of them would bore a hairline tunnel or slit through the solid.
// A part thinner than a cell, which no node falls in, is found by the midpoints of the
// tetrahedra's edges on the other side of the surface from both ends; where the sharp-feature
// pass does not mend it, and round edges it leaves more than half a cell off, the cells are
// cut four times finer and joined to the lattice by transition cells (mesh_refine.hpp),
// keeping every guarantee above. Last, points of the surface the mesh passes more than 0.4
// cells from, found by Newton round its bent parts as the tests' independent check finds
// them, become vertices splitting a triangle near them, where the split keeps those
// guarantees (mesh_cover.hpp).
#pragma once

#include "interp/engine.hpp"
#include "interp/ir/ir.hpp"
#include "interp/mesh_cover.hpp"
#include "interp/mesh_features.hpp"
#include "runtime/grid.hpp"
#include "runtime/mesh.hpp"

#include <array>
#include <cstddef>

namespace fortu {

/// What one meshing run did (for --stats and the benchmark).
struct MeshStats {
    std::size_t boxes = 0;            ///< octree boxes tested with intervals
    std::size_t leaves = 0;           ///< leaves of 8³ cells whose nodes were evaluated
    std::size_t node_evaluations = 0; ///< grid nodes evaluated (on shortened tapes)
    std::size_t edge_evaluations = 0; ///< Newton/bisection steps on crossing edges, summed
    std::size_t crossing_edges = 0;   ///< marching-tetrahedra vertices
    /// Cells whose centre is on the other side of the surface from both ends of their main
    /// diagonal, a fiftieth of a cell beyond it or more (inside the solid with the ends outside,
    /// or the reverse): a part of the solid or a hole in it thinner than a cell, which marching
    /// tetrahedra on the lattice leave out. Cells on the domain's faces (whose nodes count as
    /// outside, closing the solid) are not tried.
    std::size_t thin_cells = 0;
    std::array<double, 3> first_thin{};  ///< the centre of the one with the lowest cell index
    /// The cells refinement started from (mesh_refine.hpp): the thin cells whose centre the
    /// sharp-feature pass's mesh left on the wrong side, and the cells round the edges it left
    /// more than half a cell off (a wedge thinner than a cell that no centre falls in).
    std::size_t refine_seeds = 0;
    std::size_t refined_cells = 0;       ///< cells cut kRefine times finer per axis, these and the cells a part goes on into
    std::size_t transition_cells = 0;    ///< cells round them cut into cones from their centre
    /// Cells a refined part goes on into that were left unrefined: kMaxRefinedCells reached.
    std::size_t refinement_left = 0;
    std::array<double, 3> first_left{};  ///< the centre of the one with the lowest cell index
    FeatureStats features;            ///< the sharp features put back (mesh_features.hpp)
    CoverStats cover;                 ///< surface points far from the mesh put in (mesh_cover.hpp)
};

/// The closed mesh of `root`'s zero surface on `grid` (3D, at least 2 nodes per axis; its
/// nodes are the mesh's lattice, grid.x.nodes − 1 cells along X). Positive is inside; zero,
/// NaN and the domain's outer nodes are outside, but a point where the field is NaN takes its
/// value from 1e-7 of a cell beside it, and a zero inside the solid (zero_inside,
/// mesh_features.hpp) counts as inside: 0/0 on a plane, or two parts joined on one, is not a
/// slit in it.
/// Throws std::invalid_argument for a 2D grid.
Mesh extract_mesh(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options = {},
                  MeshStats* stats = nullptr);

}  // namespace fortu
