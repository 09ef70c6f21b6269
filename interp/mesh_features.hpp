// interp/mesh_features.hpp — sharp edges and corners put back into a marching-tetrahedra
// mesh (the mesher's last pass, interp/mesher.cpp).
//
// Why: an R-function solid's edges are exactly where both operands of one R-operation vanish,
// and its corners where such edges meet; marching tetrahedra keep vertices on grid edges and
// so cut them off by up to a cell. From each cell whose surface normals disagree, the pass
// finds a point of the edge curve with the `fortu singular` machinery (Newton's method on
// (φ, ψ) = 0 with exact gradients, the minimum-norm step) and traces the curve cell to cell,
// putting a vertex where it crosses each cell face (Newton on φ, ψ and the face's plane). Each
// cell it crosses is re-triangulated: the crossings go into the marching-tetrahedra segments
// on their faces (the same segment from both cells, so the neighbours still share their
// boundary), consecutive crossings are joined by an edge that cuts the cell's patch into
// polygons, each triangulated with least area; a corner's cell gets a fan from the corner
// (Kobbelt et al.'s extended marching cubes). The edges are then chains of mesh edges with no
// gaps, the polyline through the curve's crossings of the lattice.
// Every change keeps the boundary a neighbour sees, so watertightness, manifoldness and
// orientation stay as the mesher made them; a cell is changed only when each new polygon,
// projected along its mean normal, keeps its triangles' orientation and has a simple boundary
// (so it cannot fold or cross itself), the polygons do not cross each other, no triangle edge
// lies across a face, and the face segments with crossings in do not cross. A cell that fails
// is fanned from a point of its edge curve over its boundary, crossings included; failing
// that, it gives up its crossings and its neighbours are redone without them.
// Features on the lattice (a crossing on a grid edge or node, a corner on a grid plane): the
// point is snapped exactly there and shared by every cell around it: each crossing goes into
// one patch-boundary segment chosen once for all cells (and, where the curve passes a node
// into a cell diagonally across, into one of that cell's too: the cell between takes the
// vertex twice and is triangulated as two loops), a corner the solid surrounds on both
// sides of a grid plane is fanned over the joined patches of the cells around it; the two
// cells beside a piece of edge along a grid edge with the solid on both sides of a grid plane
// through it are redone together, the face between them inside; so is a cell whose patch is
// two sheets (a strip of solid along a face, split by its Kuhn diagonal) with the cell beyond
// that face. A face segment may take several crossings, in their order along it.
// Features in cells marching tetrahedra left empty (an acute edge's wedge thinner than a cell,
// a tip whose cell holds no node inside): their crossings and tips, joined by the traced links,
// form a tree whose leaves are crossings on patches; the patches of a block of cells around it
// are redone together, cut along the tree, so the surface reaches the edge and its corners.
// A node the curve passes from one cell into the one across it in all three axes is such a
// tree's node too, its block only the cells around it: no segment can take it without
// folding those cells.
// A closed crease whose trees are all gaps (a concave crease shallower than a cell: its
// crossings fall in cells with every node inside, and the trees, sharing the crossings
// between them, would compete for each other's cells) is redone as one band: the annulus of
// surface round it, within a cell or two, replaced by two strips of least area from its
// boundary rings to the crease.
// Last, on the finished mesh: where a run of an edge's crossings is still off the mesh between
// two on it, marching tetrahedra cut across the edge's wedge (a chamfer: triangles with
// vertices on both operands' faces); the chamfer, found by the faces its vertices lie on, is
// replaced by two strips from its sides to the crossings, so the edge is on the mesh there too.
// Where the domain cuts a model with edges of its own, the caps that close it are operands
// (the model MIN each cap's plane), so their rims, the domain's edges and the corners where the
// model's edges run into them are put back the same way.
#pragma once

#include "interp/ir/ir.hpp"
#include "runtime/grid.hpp"
#include "runtime/mesh.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fortu {

struct FeatureStats {
    std::size_t cells_tested = 0;     ///< cells whose normals disagree
    std::size_t edge_vertices = 0;    ///< vertices where an R-operation's edge curve crosses a cell face
    std::size_t corner_vertices = 0;  ///< vertices where edges meet
    std::size_t chain_edges = 0;      ///< mesh edges along the edge curves (cells redone count again)
    // The crossings the finished mesh does not reach are counted by the cover pass
    // (CoverStats::crossings_off_mesh), on the mesh as written.
};

/// Where the domain cuts the solid: the mesher closes it there with caps, `margin` of a step
/// inside the faces marked (faces[2·axis]: the lower one, faces[2·axis + 1]: the upper).
struct DomainCaps {
    std::array<bool, 6> faces{};
    double margin = 0;
};

/// Where the model is exactly zero, it is inside the solid, not on its surface, when a
/// ten-millionth of a cell away along the 26 directions of zero_probe it is nowhere negative
/// or NaN, somewhere positive, and exactly zero both ways along one of them: two parts joined
/// on a plane or a line (Chainik's lid and body at z = 3, B & 0 = 0 and 0 | 0 = 0). The mesher
/// counts such nodes inside, where a plane of them would be a slit through the solid; the
/// sharp-feature pass takes the operations' edges there for inside. A zero on the surface has
/// outside points round it; where all 26 directions miss them (a concave edge whose outside
/// wedge is thin), it is still not zero along a line through it, to the last bit.
inline constexpr int kZeroProbes = 26;
inline constexpr double kZeroProbeFraction = 1e-7;
/// Probe k's offset in cells: each of −1, 0, 1 per axis but (0, 0, 0).
inline std::array<double, 3> zero_probe(int k) {
    const int code = k < 13 ? k : k + 1;  // skip the centre, code 13
    return {kZeroProbeFraction * (code % 3 - 1), kZeroProbeFraction * (code / 3 % 3 - 1), kZeroProbeFraction * (code / 9 - 1)};
}
/// The probe toward `direction`'s signs (an edge's, in cells): zero_probe's inverse.
inline int zero_probe_toward(const std::array<double, 3>& direction) {
    int code = 13;  // (dx + 1) + 3 (dy + 1) + 9 (dz + 1)
    for (int a = 0, scale = 1; a < 3; ++a, scale *= 3) code += scale * (direction[std::size_t(a)] > 0 ? 1 : direction[std::size_t(a)] < 0 ? -1 : 0);
    return code < 13 ? code : code - 1;
}
/// Whether the probes are exactly zero both ways along probe k's direction (k and its
/// opposite, kZeroProbes − 1 − k).
inline bool zero_both_ways(const double* probes, int k) { return probes[k] == 0 && probes[kZeroProbes - 1 - k] == 0; }
/// Whether the probes are exactly zero both ways along one of their directions: the zero
/// is part of a plane or a line of them.
inline bool on_zero_line(const double* probes) {
    for (int k = 0; k < kZeroProbes / 2; ++k)
        if (zero_both_ways(probes, k)) return true;
    return false;
}
/// The verdict from the model's values at the kZeroProbes probes.
inline bool zero_inside(const double* probes) {
    bool positive = false;
    for (int k = 0; k < kZeroProbes; ++k) {
        if (!(probes[k] >= 0)) return false;
        positive = positive || probes[k] > 0;
    }
    return positive && on_zero_line(probes);
}

/// Rewrites `mesh` (made on `grid`'s lattice; `triangle_cells[t]` the cell of triangle t,
/// x + cells_x·(y + cells_y·z)) with vertices on the sharp features of `root`'s R-operations
/// and of the `caps` that close it where the domain cuts it. The `frozen` cells (sorted: those
/// the mesher refined for thin parts, mesh_refine.hpp) keep their triangles, and their faces
/// take no crossing: the features there stay as the finer tetrahedra cut them. The cells
/// joining them (cones over their faces) are redone as the lattice's cells are.
/// A cell with a part thinner than a cell (or a hole) in it that marching tetrahedra left out,
/// by lattice index, and a point in that part (the midpoint of a tetrahedron's edge, the
/// mesher's find_thin_cells): inside the solid, or not.
struct ThinPart {
    uint64_t cell;
    bool inside;
    std::array<double, 3> point;
    bool operator<(const ThinPart& other) const { return cell < other.cell; }
};

/// What the mesher asks of the pass before the pass changes the mesh (mesh_refine.hpp).
struct RefineQuery {
    /// The thin parts, sorted by cell. Where the pass put a part's edges back, the finished
    /// mesh has its point on the side the field says; elsewhere it does not.
    std::vector<ThinPart> thin;
    /// Their cells, sorted.
    std::vector<uint64_t> thin_cells() const {
        std::vector<uint64_t> cells;
        for (const ThinPart& part : thin) cells.push_back(part.cell);
        return cells;
    }
    /// Out: the cells to refine before the pass runs again, sorted: those thin cells whose
    /// point the finished mesh leaves on the wrong side, and the cells round the
    /// traced crossings more than half a cell off it (a wedge thinner than a cell whose cells
    /// could not be redone). Empty: the mesh was changed.
    std::vector<uint64_t> refine;
    /// Out, with `refine`: the cells of the corners and the concave creases' bands the pass put
    /// back, sorted; refining a cell beside them would cut theirs into cones (mesh_refine.hpp),
    /// where the pass, run again, may not put them back.
    std::vector<uint64_t> keep;
};

/// Unused vertices are dropped; the order of the result depends on the input only. The
/// crossings left off the mesh are measured for a `query`: where it finds cells to refine, the
/// mesh is left as it was (false), for the mesher to refine them and call again. When the mesh
/// is changed, the crossings that are not its vertices are added to `crossings_left` (points
/// of the edges: the cover pass puts those it finds far from the mesh in, and measures them
/// all on the finished mesh, for CoverStats).
bool sharpen_features(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh,
                      const std::vector<uint64_t>& triangle_cells, const DomainCaps& caps,
                      const std::vector<uint64_t>& frozen = {}, FeatureStats* stats = nullptr,
                      RefineQuery* query = nullptr, std::vector<std::array<double, 3>>* crossings_left = nullptr);

}  // namespace fortu
