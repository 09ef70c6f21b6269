// interp/mesh_refine.hpp — the tetrahedra of the cells the mesher cuts finer where the solid has
// a part thinner than a cell, and of the cells that join them to the rest of the lattice.
//
// Why: marching tetrahedra see the solid only at the lattice's nodes, so a blade, a sheet or a
// slit thinner than a cell that no node falls in is left out of the mesh, its surface a cell
// or more from it. Where the mesher finds one (a cell with the midpoint of one of its
// tetrahedra's edges on the other side of the surface from both ends), the cell is cut
// kRefine times finer along each axis, each small cube split into Kuhn's six tetrahedra as
// the lattice's cubes are.
// Every cell that shares an edge with a refined one (a transition cell) is split into cones
// from its centre over its faces, each face triangulated as the cell across it sees it:
// - a face of a refined cell: the fine lattice's own split of it (small squares, each cut by
//   its Kuhn diagonal);
// - a face with an edge a refined cell has split: a fan from the face's centre over its
//   boundary, the split edges' fine nodes included;
// - any other face: its two Kuhn triangles, as the cell across it (maybe unrefined) cuts it.
// Each edge is split into kRefine pieces when a refined cell has it, and kept whole otherwise,
// alike in every cell round it. So the tetrahedra still fill space face to face, and marching
// tetrahedra's guarantees (watertight, manifold, outward, free of self-intersections) hold as
// on the plain lattice. All points are nodes of the lattice refined kRefine times, named by
// integer coordinates there, so the cells round a point share its value and its vertices.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace fortu {

/// How many times finer a refined cell is along each axis (even: the centre is a fine node).
inline constexpr int kRefine = 4;

/// A point of the lattice refined kRefine times: integer coordinates, each below 2^21.
using FinePoint = std::array<int64_t, 3>;
inline uint64_t fine_key(const FinePoint& p) { return uint64_t(p[0]) | uint64_t(p[1]) << 21 | uint64_t(p[2]) << 42; }
inline FinePoint fine_point(uint64_t key) {
    return {int64_t(key & 0x1fffff), int64_t(key >> 21 & 0x1fffff), int64_t(key >> 42 & 0x1fffff)};
}

/// The refined cells of a lattice of `cells` cells per axis (ids x + cells_x·(y + cells_y·z),
/// as the mesher numbers them) and the transition cells round them.
class RefinedCells {
public:
    explicit RefinedCells(const std::array<int, 3>& cells) : cells_(cells) {}
    /// Whether the fine lattice's coordinates fit fine_key.
    static bool fits(const std::array<int, 3>& cells) {
        for (int c : cells)
            if (int64_t(c) * kRefine >= (int64_t(1) << 21)) return false;
        return true;
    }

    /// Adds cells (kept sorted).
    void refine(const std::vector<uint64_t>& cells);
    bool refined(uint64_t cell) const;
    std::size_t size() const { return refined_.size(); }
    const std::vector<uint64_t>& refined_cells() const { return refined_; }

    std::array<int64_t, 3> coords(uint64_t cell) const {
        return {int64_t(cell % uint64_t(cells_[0])), int64_t(cell / uint64_t(cells_[0]) % uint64_t(cells_[1])),
                int64_t(cell / (uint64_t(cells_[0]) * uint64_t(cells_[1])))};
    }
    /// The cell at coords, or UINT64_MAX outside the lattice.
    uint64_t cell_at(const std::array<int64_t, 3>& c) const;

    /// The refined cells and those sharing an edge with one, sorted: the cells whose
    /// tetrahedra are not the plain lattice's.
    std::vector<uint64_t> changed_cells() const;
    /// Whether refining `cell` would change one of `cells` (sorted): it or a cell sharing an
    /// edge with it is one.
    bool would_change(uint64_t cell, const std::vector<uint64_t>& cells) const;

    /// The tetrahedra of a changed cell, as four fine points each (in no particular
    /// orientation), appended to `out`.
    void tetrahedra(uint64_t cell, std::vector<std::array<FinePoint, 4>>& out) const;

    /// The fine nodes of a refined cell's (kRefine + 1)³ lattice, x fastest.
    std::vector<FinePoint> nodes_of(uint64_t cell) const;

private:
    /// Whether the lattice edge from coarse node g along `axis` is split: a refined cell has it.
    bool edge_split(const std::array<int64_t, 3>& g, int axis) const;
    /// The triangles of the face of cell c on `axis`'s lower (side 0) or upper side.
    void face_triangles(const std::array<int64_t, 3>& c, int axis, int side, std::vector<std::array<FinePoint, 3>>& out) const;

    std::array<int, 3> cells_;
    std::vector<uint64_t> refined_;
};

}  // namespace fortu
