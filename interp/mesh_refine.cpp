// interp/mesh_refine.cpp — which cells are refined or join them, and how each is cut into
// tetrahedra (mesh_refine.hpp).
#include "interp/mesh_refine.hpp"

#include <algorithm>

namespace fortu {
namespace {

/// Kuhn's split of a cube, corners by bits (1: +X, 2: +Y, 4: +Z), as the mesher's lattice.
constexpr int kKuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

}  // namespace

void RefinedCells::refine(const std::vector<uint64_t>& cells) {
    refined_.insert(refined_.end(), cells.begin(), cells.end());
    std::sort(refined_.begin(), refined_.end());
    refined_.erase(std::unique(refined_.begin(), refined_.end()), refined_.end());
}

bool RefinedCells::refined(uint64_t cell) const { return std::binary_search(refined_.begin(), refined_.end(), cell); }

uint64_t RefinedCells::cell_at(const std::array<int64_t, 3>& c) const {
    for (int a = 0; a < 3; ++a)
        if (c[std::size_t(a)] < 0 || c[std::size_t(a)] >= cells_[std::size_t(a)]) return UINT64_MAX;
    return uint64_t(c[0]) + uint64_t(cells_[0]) * (uint64_t(c[1]) + uint64_t(cells_[1]) * uint64_t(c[2]));
}

/// Calls visit(cell) for `cell` and the cells sharing an edge with it (not only a corner).
template <class Visit>
void for_edge_neighbours(const RefinedCells& lattice, uint64_t cell, const Visit& visit) {
    const auto c = lattice.coords(cell);
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                if (dx != 0 && dy != 0 && dz != 0) continue;
                const uint64_t other = lattice.cell_at({c[0] + dx, c[1] + dy, c[2] + dz});
                if (other != UINT64_MAX) visit(other);
            }
}

std::vector<uint64_t> RefinedCells::changed_cells() const {
    std::vector<uint64_t> out;
    for (uint64_t cell : refined_) for_edge_neighbours(*this, cell, [&](uint64_t other) { out.push_back(other); });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

bool RefinedCells::would_change(uint64_t cell, const std::vector<uint64_t>& cells) const {
    bool found = false;
    for_edge_neighbours(*this, cell, [&](uint64_t other) { found = found || std::binary_search(cells.begin(), cells.end(), other); });
    return found;
}

bool RefinedCells::edge_split(const std::array<int64_t, 3>& g, int axis) const {
    const int b = (axis + 1) % 3, d = (axis + 2) % 3;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            std::array<int64_t, 3> c = g;
            c[std::size_t(b)] -= i;
            c[std::size_t(d)] -= j;
            const uint64_t cell = cell_at(c);
            if (cell != UINT64_MAX && refined(cell)) return true;
        }
    return false;
}

void RefinedCells::face_triangles(const std::array<int64_t, 3>& c, int axis, int side,
                                  std::vector<std::array<FinePoint, 3>>& out) const {
    const int b = (axis + 1) % 3, d = (axis + 2) % 3;
    constexpr int r = kRefine;
    FinePoint origin{c[0] * r, c[1] * r, c[2] * r};
    origin[std::size_t(axis)] += side * r;
    auto at = [&](int i, int j) {
        FinePoint p = origin;
        p[std::size_t(b)] += i;
        p[std::size_t(d)] += j;
        return p;
    };
    std::array<int64_t, 3> across = c;
    across[std::size_t(axis)] += side ? 1 : -1;
    const uint64_t neighbour = cell_at(across);
    if (refined(cell_at(c)) || (neighbour != UINT64_MAX && refined(neighbour))) {
        for (int i = 0; i < r; ++i)
            for (int j = 0; j < r; ++j) {
                out.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                out.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            }
        return;
    }
    std::array<int64_t, 3> g = c;  // the face's lowest coarse node
    g[std::size_t(axis)] += side;
    auto shifted = [&](int db, int dd) {
        std::array<int64_t, 3> n = g;
        n[std::size_t(b)] += db;
        n[std::size_t(d)] += dd;
        return n;
    };
    const bool split[4] = {edge_split(g, b), edge_split(shifted(1, 0), d), edge_split(shifted(0, 1), b), edge_split(g, d)};
    if (!split[0] && !split[1] && !split[2] && !split[3]) {
        out.push_back({at(0, 0), at(r, 0), at(r, r)});
        out.push_back({at(0, 0), at(0, r), at(r, r)});
        return;
    }
    // Round the boundary: (0,0) → (r,0) → (r,r) → (0,r) → (0,0), each split edge node by node.
    std::vector<FinePoint> loop;
    const int starts[4][2] = {{0, 0}, {r, 0}, {r, r}, {0, r}}, steps[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (int e = 0; e < 4; ++e) {
        const int stride = split[e] ? 1 : r;
        for (int k = 0; k < r; k += stride) loop.push_back(at(starts[e][0] + k * steps[e][0], starts[e][1] + k * steps[e][1]));
    }
    const FinePoint centre = at(r / 2, r / 2);
    for (std::size_t k = 0; k < loop.size(); ++k) out.push_back({centre, loop[k], loop[(k + 1) % loop.size()]});
}

void RefinedCells::tetrahedra(uint64_t cell, std::vector<std::array<FinePoint, 4>>& out) const {
    constexpr int r = kRefine;
    const auto c = coords(cell);
    if (refined(cell)) {
        for (int z = 0; z < r; ++z)
            for (int y = 0; y < r; ++y)
                for (int x = 0; x < r; ++x)
                    for (const auto& tet : kKuhn) {
                        std::array<FinePoint, 4> t;
                        for (int k = 0; k < 4; ++k)
                            t[std::size_t(k)] = {c[0] * r + x + (tet[k] & 1), c[1] * r + y + (tet[k] >> 1 & 1), c[2] * r + z + (tet[k] >> 2)};
                        out.push_back(t);
                    }
        return;
    }
    const FinePoint centre{c[0] * r + r / 2, c[1] * r + r / 2, c[2] * r + r / 2};
    std::vector<std::array<FinePoint, 3>> faces;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) face_triangles(c, axis, side, faces);
    for (const auto& f : faces) out.push_back({centre, f[0], f[1], f[2]});
}

std::vector<FinePoint> RefinedCells::nodes_of(uint64_t cell) const {
    constexpr int r = kRefine;
    const auto c = coords(cell);
    std::vector<FinePoint> out;
    out.reserve((r + 1) * (r + 1) * (r + 1));
    for (int z = 0; z <= r; ++z)
        for (int y = 0; y <= r; ++y)
            for (int x = 0; x <= r; ++x) out.push_back({c[0] * r + x, c[1] * r + y, c[2] * r + z});
    return out;
}

}  // namespace fortu
