// interp/mesher.cpp — the octree walk, the leaves' node values, the edges' Newton solves,
// the tetrahedra's triangles and the final welding of vertices shared between leaves.
#include "interp/mesher.hpp"

#include "interp/box_simplify.hpp"
#include "interp/interval.hpp"
#include "interp/mesh_features.hpp"
#include "interp/mesh_cover.hpp"
#include "interp/mesh_refine.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/lane_points.hpp"
#include "interp/parallel.hpp"
#include "interp/tape.hpp"
#include "interp/written_r_operations.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace fortu {
namespace {

using ir::Dual;
using Vec = std::array<double, 3>;

constexpr int kLeafCells = 8;                 ///< a leaf is 8³ cells, 9³ nodes (4³ measured: no faster on bear.vm)
constexpr int kLeafNodes = kLeafCells + 1;
/// Vertices stay this fraction of their edge away from its nodes: no two vertices coincide and
/// no triangle degenerates, even after STL rounds coordinates to float32 (6e-8 relative).
constexpr double kEdgeMargin = 1e-3;
/// Newton/bisection stops when a step along the edge was below this fraction of it: Newton's
/// steps shrink quadratically, so the point is then exact to round-off on smooth fields.
constexpr double kEdgeTolerance = 1e-7;
constexpr int kMaxEdgeSteps = 64;
constexpr int kEdgeLanes = 64;                ///< edges solved together on one tape run
/// A thin cell's centre is this many cells beyond the surface or more, to first order: a ball
/// of radius 7 cells cuts main diagonals in caps 0.01 to 0.02 cells deep.
constexpr double kThinDepth = 0.02;
/// The midpoint of a face's diagonal or a lattice edge, this many: the ball of radius 7 cells
/// whose surface passes through nodes (0.7 through (0.6, 0.3, 0.2) on cells of 0.1) has face
/// diagonals between them 0.036 cells deep in it, and TeaCup's handle meets its body in a
/// hollow 0.023 deep, both marching tetrahedra's usual error; new_Chainik's spout, a bore the
/// centres miss, is 0.07 to 0.13 deep at the midpoints that find it (24 nodes).
constexpr double kThinDepthBetween = 0.05;
/// At most this many cells are refined (mesh_refine.hpp): (kRefine + 1)³ = 125 points each,
/// about a hundred megabytes of values at most; a part thinner than a cell that goes on
/// beyond is left out there, and said (MeshStats::refinement_left).
constexpr std::size_t kMaxRefinedCells = 1 << 12;
/// Times the sharp-feature pass may send cells back to be refined where it left an edge more
/// than half a cell off (each time it runs again: Tor1 at 65 nodes, 1.3 s a pass).
constexpr int kRefinePasses = 1;
/// Where the formula is NaN only on a plane, a line or a point (0/0: ARCTAN(Y/X) on the Z
/// axis, ABS(X)/X on X = 0), a node or an edge point there takes the field's value this
/// fraction of a cell away, along kNudge: a node on such a plane would otherwise count as
/// outside and cut a hairline slit or tunnel through the solid (Chainik at 129 nodes, down
/// its axis). Where the field is NaN around the point too, it stays NaN.
constexpr double kNudgeFraction = 1e-7;
/// A direction off every grid plane and line, and off their diagonals.
constexpr double kNudge[3] = {1.0, 0.7548776662466927, 0.5698402909980532};

// ---- The Kuhn split of a cube and the triangles of each sign case -------------------------

/// Cube corners by bits (1: +X, 2: +Y, 4: +Z). The six tetrahedra share the diagonal 0–7;
/// every edge of them joins a corner to one whose bits include its own.
constexpr int kTetCorners[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

/// A triangle vertex: the edge between two corners of the cube (inside first).
struct CaseEdge {
    uint8_t inside, outside;
};
struct CaseTriangles {
    int count = 0;
    CaseEdge tri[2][3];
};

Vec corner_position(int c) { return {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}; }

/// A triangle of a tetrahedron: its vertices' edges, each (inside corner, outside corner).
using TetTriangle = std::array<std::array<int, 2>, 3>;

/// The triangles marching tetrahedra put in a tetrahedron with corners `corner` (in any
/// order) of which `inside` are inside (bit k: corner k), oriented outward; how many (0-2).
/// One inside or outside corner: a triangle; two: the quad (a,c) (b,c) (b,d) (a,d), split
/// along (a,c)–(b,d). The normal points away from the inside corners: which side they are on
/// does not change as vertices move along their edges, so the edges' midpoints decide.
int tetrahedron_triangles(const std::array<Vec, 4>& corner, int inside, TetTriangle tri[2]) {
    int in[4], out[4], ins = 0, outs = 0;
    for (int k = 0; k < 4; ++k) ((inside >> k) & 1 ? in[ins++] : out[outs++]) = k;
    if (ins == 0 || outs == 0) return 0;
    int count = 1;
    if (ins == 1) tri[0] = {{{in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]}}};
    else if (ins == 3) tri[0] = {{{in[0], out[0]}, {in[1], out[0]}, {in[2], out[0]}}};
    else {
        count = 2;
        tri[0] = {{{in[0], out[0]}, {in[1], out[0]}, {in[1], out[1]}}};
        tri[1] = {{{in[0], out[0]}, {in[1], out[1]}, {in[0], out[1]}}};
    }
    for (int k = 0; k < count; ++k) {
        Vec m[3];
        for (int v = 0; v < 3; ++v)
            for (int a = 0; a < 3; ++a) {
                const auto& e = tri[k][std::size_t(v)];
                m[v][std::size_t(a)] = (corner[std::size_t(e[0])][std::size_t(a)] + corner[std::size_t(e[1])][std::size_t(a)]) / 2;
            }
        const Vec u{m[1][0] - m[0][0], m[1][1] - m[0][1], m[1][2] - m[0][2]};
        const Vec w{m[2][0] - m[0][0], m[2][1] - m[0][1], m[2][2] - m[0][2]};
        const Vec n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        const Vec& p = corner[std::size_t(in[0])];
        const double side = n[0] * (m[0][0] - p[0]) + n[1] * (m[0][1] - p[1]) + n[2] * (m[0][2] - p[2]);
        if (side < 0) std::swap(tri[k][1], tri[k][2]);
    }
    return count;
}

/// The table, per tetrahedron of the Kuhn split and per mask of its inside corners (bit k:
/// tet corner k), in cube corners.
struct CaseTable {
    CaseTriangles cases[6][16];
    CaseTable() {
        for (int t = 0; t < 6; ++t) {
            std::array<Vec, 4> corner;
            for (int k = 0; k < 4; ++k) corner[std::size_t(k)] = corner_position(kTetCorners[t][k]);
            for (int mask = 1; mask < 15; ++mask) {
                TetTriangle tri[2];
                CaseTriangles& c = cases[t][mask];
                c.count = tetrahedron_triangles(corner, mask, tri);
                for (int k = 0; k < c.count; ++k)
                    for (int v = 0; v < 3; ++v)
                        c.tri[k][v] = CaseEdge{uint8_t(kTetCorners[t][tri[k][std::size_t(v)][0]]), uint8_t(kTetCorners[t][tri[k][std::size_t(v)][1]])};
            }
        }
    }
};

const CaseTable& case_table() {
    static const CaseTable table;
    return table;
}

// ---- Leaves --------------------------------------------------------------------------------

/// A vertex reference inside a leaf: bits 0–11 the owner's edge id (node·8 + direction, node =
/// x + 8y + 64z in the owner), bits 12–14 which neighbour owns it (+X, +Y, +Z).
using EdgeRef = uint16_t;

struct LeafMesh {
    std::array<int, 3> leaf{};                   ///< leaf coordinates
    std::vector<uint16_t> edges;                 ///< owned crossing edges, increasing ids
    std::vector<Vec> positions, normals;         ///< per owned edge
    std::vector<std::array<EdgeRef, 3>> triangles;
    std::vector<uint16_t> triangle_cells;        ///< per triangle, its cell: x + 8y + 64z in the leaf
};

struct Lattice {
    double min[3], step[3];
    int nodes[3], cells[3], leaves[3];
    double at(int axis, int i) const { return min[axis] + i * step[axis]; }
};

/// Scratch reused by one worker from leaf to leaf.
struct Worker {
    std::vector<Interval> ranges;
    BoxScratch box;
    std::vector<std::unique_ptr<Tape>> tapes;    ///< one per depth
    Tape leaf_tape;                              ///< the leaf's tape in max-live slots
    SlotScratch slot_scratch;
    std::vector<double> lanes;
    std::vector<double*> slots;
    std::vector<Dual> dual_lanes;
    std::vector<Dual*> dual_slots;
    std::vector<LeafMesh> leaves;
    std::vector<double> nudged_lanes;            ///< the whole model's tape at nudged points
    std::vector<double*> nudged_slots;
    std::vector<Dual> nudged_dual_lanes;
    std::vector<Dual*> nudged_dual_slots;
    MeshStats stats;
    std::vector<ThinPart> thin_cells;  ///< find_thin_cells
    std::array<bool, 6> cut_faces{};  ///< the domain's faces with a node inside the model, in leaves with triangles
};

class Mesher {
public:
    /// `whole`: the model's tape in max-live slots, for points whose field is NaN or zero
    /// (read_beside).
    /// `ssa`: the model's pruning tape, which leaves shorten for their boxes.
    Mesher(const Grid& grid, const Tape& ssa, const Tape& whole) : ssa_(ssa), whole_(whole) {
        const Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
        for (int a = 0; a < 3; ++a) {
            l_.min[a] = axes[a]->min;
            l_.step[a] = axes[a]->step();
            l_.nodes[a] = axes[a]->nodes;
            l_.cells[a] = axes[a]->nodes - 1;
            l_.leaves[a] = (l_.cells[a] + kLeafCells - 1) / kLeafCells;
        }
    }
    const Lattice& lattice() const { return l_; }

    /// A box of leaves [lo, lo + size) per axis (clipped to the lattice).
    struct Box {
        std::array<int, 3> lo;
        int size;
    };

    enum class Verdict { Empty, Leaf, Split };

    /// Tests the box with intervals. Empty: no surface can cross it. Otherwise `simplified`
    /// holds the tape shortened for it and `all_inside` says the intervals found it inside
    /// (a box on the domain's border still meshes its cap there).
    Verdict decide(const Box& box, const Tape& tape, Worker& w, Tape& simplified, bool& all_inside) const {
        ++w.stats.boxes;
        std::array<Interval, 3> axes;
        bool border = false;
        for (int a = 0; a < 3; ++a) {
            const int c0 = box.lo[a] * kLeafCells, c1 = std::min((box.lo[a] + box.size) * kLeafCells, l_.cells[a]);
            axes[a] = {std::min(l_.at(a, c0), l_.at(a, c1)), std::max(l_.at(a, c0), l_.at(a, c1)), false};
            border |= c0 == 0 || c1 == l_.cells[a];
        }
        evaluate_intervals(tape, axes, w.ranges);
        const Interval& r = w.ranges[tape.root_slot];
        if (r.hi <= 0 && !r.maybe_nan) return Verdict::Empty;
        all_inside = r.positive();
        if (all_inside && !border) return Verdict::Empty;
        if (all_inside) simplified = tape;
        else simplify_for_sign(tape, w.ranges, w.box, simplified, /*keep_values=*/true);
        return box.size == 1 ? Verdict::Leaf : Verdict::Split;
    }

    std::vector<Box> split(const Box& box) const {
        std::vector<Box> parts;
        const int half = box.size / 2;
        for (int k = 0; k < 8; ++k) {
            Box b{{box.lo[0] + (k & 1) * half, box.lo[1] + ((k >> 1) & 1) * half, box.lo[2] + ((k >> 2) & 1) * half},
                  half};
            if (b.lo[0] < l_.leaves[0] && b.lo[1] < l_.leaves[1] && b.lo[2] < l_.leaves[2]) parts.push_back(b);
        }
        return parts;
    }

    /// Depth-first from a box whose parent's tape is `tape`.
    void walk(const Box& box, const Tape& tape, Worker& w, std::size_t depth, const std::atomic<bool>* cancel) const {
        if (cancel && cancel->load()) return;
        if (w.tapes.size() <= depth) w.tapes.push_back(std::make_unique<Tape>());
        Tape& simplified = *w.tapes[depth];
        bool all_inside = false;
        switch (decide(box, tape, w, simplified, all_inside)) {
            case Verdict::Empty: return;
            case Verdict::Leaf: mesh_leaf(box.lo, simplified, all_inside, w); return;
            case Verdict::Split:
                for (const Box& child : split(box)) walk(child, simplified, w, depth + 1, cancel);
        }
    }

    void mesh_leaf(const std::array<int, 3>& leaf, const Tape& ssa, bool all_inside, Worker& w) const {
        // Lanes cost slots × points: in SSA slots a deep model would cost gigabytes a worker.
        reallocate_slots(ssa, w.leaf_tape, w.slot_scratch);
        const Tape& tape = w.leaf_tape;
        int c0[3], nc[3], nn[3];
        for (int a = 0; a < 3; ++a) {
            c0[a] = leaf[a] * kLeafCells;
            nc[a] = std::min(kLeafCells, l_.cells[a] - c0[a]);
            nn[a] = nc[a] + 1;
        }
        const int count = nn[0] * nn[1] * nn[2];
        auto local = [&](int x, int y, int z) { return (z * nn[1] + y) * nn[0] + x; };
        // Node values: the leaf's tape over its nodes (exact values), or "inside" by intervals;
        // `evaluated` keeps them before read_beside (zeros inside the solid are zeros there),
        // apart from the lanes, which the thin cells' midpoints reuse.
        double values[kLeafNodes * kLeafNodes * kLeafNodes], evaluated[kLeafNodes * kLeafNodes * kLeafNodes];
        if (all_inside) {
            std::fill_n(values, count, 1.0);
        } else {
            bind_slots(w.lanes, w.slots, tape, kLeafNodes * kLeafNodes * kLeafNodes);
            for (auto [slot, axis] : tape.arguments) {
                double* out = w.slots[slot];
                for (int z = 0; z < nn[2]; ++z)
                    for (int y = 0; y < nn[1]; ++y)
                        for (int x = 0; x < nn[0]; ++x) {
                            const int g[3] = {c0[0] + x, c0[1] + y, c0[2] + z};
                            out[local(x, y, z)] = l_.at(axis, g[axis]);
                        }
            }
            for (auto [slot, value] : tape.constants) std::fill_n(w.slots[slot], count, value);
            run_lanes<double, 0>(tape.code.data(), tape.code.size(), w.slots.data(), count);
            std::copy_n(w.slots[tape.root_slot], count, evaluated);
            std::copy_n(evaluated, count, values);
            w.stats.node_evaluations += count;
            w.stats.node_evaluations += read_beside(values, count, w.nudged_lanes, w.nudged_slots, [](int) { return true; }, [&](int i) {
                return Vec{l_.at(0, c0[0] + i % nn[0]), l_.at(1, c0[1] + i / nn[0] % nn[1]), l_.at(2, c0[2] + i / (nn[0] * nn[1]))};
            }, [](int) { return -1; });
        }
        bool inside[kLeafNodes * kLeafNodes * kLeafNodes];
        int inside_count = 0;
        std::array<bool, 6> cut{};  // the domain's faces with a node inside the model here
        for (int z = 0; z < nn[2]; ++z)
            for (int y = 0; y < nn[1]; ++y)
                for (int x = 0; x < nn[0]; ++x) {
                    const int g[3] = {c0[0] + x, c0[1] + y, c0[2] + z};
                    const int i = local(x, y, z);
                    bool border = false;
                    for (int a = 0; a < 3; ++a) {
                        const bool lower = g[a] == 0, upper = g[a] == l_.cells[a];
                        border |= lower || upper;
                        if (values[i] > 0) cut[std::size_t(2 * a)] |= lower, cut[std::size_t(2 * a + 1)] |= upper;
                    }
                    inside[i] = !border && values[i] > 0;
                    inside_count += inside[i];
                }
        ++w.stats.leaves;
        if (!all_inside) find_thin_cells(tape, c0, nc, nn, values, inside, w);
        if (inside_count == 0) return;
        for (std::size_t f = 0; f < 6; ++f) w.cut_faces[f] = w.cut_faces[f] || cut[f];  // caps here, for the feature pass

        LeafMesh m;
        m.leaf = leaf;
        // The crossing edges this leaf owns: from its nodes [0, nc) along the seven directions.
        struct Pending {
            Vec from, along;        ///< inside node, and the vector to the outside one
            double f_in, f_out;
            bool zero_end;          ///< an end is exactly zero: the edge may lie in a plane of zeros
        };
        std::vector<Pending> pending;
        for (int z = 0; z < nc[2]; ++z)
            for (int y = 0; y < nc[1]; ++y)
                for (int x = 0; x < nc[0]; ++x)
                    for (int dir = 1; dir < 8; ++dir) {
                        const int i = local(x, y, z), j = local(x + (dir & 1), y + ((dir >> 1) & 1), z + (dir >> 2));
                        if (inside[i] == inside[j]) continue;
                        const int in = inside[i] ? i : j, out = inside[i] ? j : i;
                        const int ux = x + (dir & 1) * (in == j), uy = y + ((dir >> 1) & 1) * (in == j),
                                  uz = z + (dir >> 2) * (in == j);
                        const int vx = x + (dir & 1) * (out == j), vy = y + ((dir >> 1) & 1) * (out == j),
                                  vz = z + (dir >> 2) * (out == j);
                        const Vec p{l_.at(0, c0[0] + ux), l_.at(1, c0[1] + uy), l_.at(2, c0[2] + uz)};
                        const Vec q{l_.at(0, c0[0] + vx), l_.at(1, c0[1] + vy), l_.at(2, c0[2] + vz)};
                        m.edges.push_back(uint16_t((x + kLeafCells * y + kLeafCells * kLeafCells * z) * 8 + dir));
                        pending.push_back({p, {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, values[in], values[out],
                                           (!all_inside && evaluated[in] == 0) || values[out] == 0});
                    }
        m.positions.resize(pending.size());
        m.normals.resize(pending.size());
        solve_edges(tape, pending, m, all_inside, w);

        // Triangles, tetrahedron by tetrahedron.
        const CaseTable& table = case_table();
        for (int z = 0; z < nc[2]; ++z)
            for (int y = 0; y < nc[1]; ++y)
                for (int x = 0; x < nc[0]; ++x) {
                    int corner_inside = 0;
                    for (int c = 0; c < 8; ++c)
                        corner_inside |= int(inside[local(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2))]) << c;
                    if (corner_inside == 0 || corner_inside == 255) continue;
                    for (int t = 0; t < 6; ++t) {
                        int mask = 0;
                        for (int k = 0; k < 4; ++k) mask |= ((corner_inside >> kTetCorners[t][k]) & 1) << k;
                        const CaseTriangles& cases = table.cases[t][mask];
                        for (int k = 0; k < cases.count; ++k) {
                            std::array<EdgeRef, 3> tri{};
                            for (int v = 0; v < 3; ++v) tri[v] = edge_ref(x, y, z, cases.tri[k][v]);
                            m.triangles.push_back(tri);
                            m.triangle_cells.push_back(uint16_t(x + kLeafCells * (y + kLeafCells * z)));
                        }
                    }
                }
        w.leaves.push_back(std::move(m));
    }

    /// Finds the leaf's cells holding a part thinner than a cell (or a hole) that marching
    /// tetrahedra miss (MeshStats::thin_cells), for refinement: the midpoint of one of the seven
    /// edges of Kuhn's tetrahedra a cell owns (from its lowest corner: the main diagonal, the three
    /// faces' diagonals, the three lattice edges) on the other side of the surface from both
    /// ends. Marching tetrahedra see that edge change sign nowhere, and here it changes sign
    /// twice. The centre alone (the main diagonal) misses a tunnel or blade that passes
    /// between the cells' centres: new_Chainik's spout, a bore 0.2 wide on cells of 0.63, meets
    /// faces' and edges' midpoints, which lie half a cell apart. Only cells with a node as near
    /// zero as the largest step between neighbouring nodes of the leaf are tried (a part
    /// thinner than a cell lies within a cell of their nodes, so their values are within about
    /// that step of zero): their midpoints in one batch of lanes on the leaf's tape. Trying
    /// every cell cost bear.vm 25% more instructions at 129 nodes.
    void find_thin_cells(const Tape& tape, const int* c0, const int* nc, const int* nn, const double* values,
                         const bool* inside, Worker& w) const {
        auto node = [&](int x, int y, int z) { return (z * nn[1] + y) * nn[0] + x; };
        const int nodes = nn[0] * nn[1] * nn[2];
        double step = 0;  // the largest change between neighbouring nodes
        for (int row = 0; row < nn[1] * nn[2]; ++row)
            for (int i = row * nn[0]; i + 1 < (row + 1) * nn[0]; ++i) step = std::max(step, std::fabs(values[i + 1] - values[i]));
        for (int slab = 0; slab < nn[2]; ++slab)
            for (int i = slab * nn[0] * nn[1]; i + nn[0] < (slab + 1) * nn[0] * nn[1]; ++i)
                step = std::max(step, std::fabs(values[i + nn[0]] - values[i]));
        for (int i = 0; i + nn[0] * nn[1] < nodes; ++i) step = std::max(step, std::fabs(values[i + nn[0] * nn[1]] - values[i]));
        // Per node, then per cell by pairs along each axis: bit 0 all inside, bit 1 any inside,
        // bit 2 any as near zero as `step`.
        uint8_t flags[kLeafNodes * kLeafNodes * kLeafNodes];
        for (int i = 0; i < nodes; ++i) flags[i] = uint8_t(inside[i] * 3 | (std::fabs(values[i]) <= step) << 2);
        auto join = [](uint8_t p, uint8_t q) { return uint8_t((p & q & 1) | ((p | q) & 6)); };
        for (int i = 0; i + 1 < nodes; ++i) flags[i] = join(flags[i], flags[i + 1]);
        for (int i = 0; i + nn[0] < nodes; ++i) flags[i] = join(flags[i], flags[i + nn[0]]);
        for (int i = 0; i + nn[0] * nn[1] < nodes; ++i) flags[i] = join(flags[i], flags[i + nn[0] * nn[1]]);
        // The edges' directions as the leaf's crossing edges number them (bit 0 x, 1 y, 2 z),
        // the main diagonal first: a cell is recorded once, at the first midpoint found.
        constexpr int kDirections[7] = {7, 3, 5, 6, 1, 2, 4};
        std::array<uint16_t, kLeafCells * kLeafCells * kLeafCells * 7> tried;  // (cell x + 8y + 64z) · 8 + direction
        int count = 0;
        for (int z = 0; z < nc[2]; ++z)
            for (int y = 0; y < nc[1]; ++y)
                for (int x = 0; x < nc[0]; ++x) {
                    if (!(flags[node(x, y, z)] & 4)) continue;  // of the cell whose lowest corner this is
                    const int g[3] = {c0[0] + x, c0[1] + y, c0[2] + z};
                    bool border = false;
                    for (int a = 0; a < 3; ++a) border |= g[a] == 0 || g[a] + 1 == l_.cells[a];
                    if (border) continue;  // a cell the cap closes
                    const int from = node(x, y, z);
                    for (int dir : kDirections) {
                        const int to = node(x + (dir & 1), y + (dir >> 1 & 1), z + (dir >> 2));
                        // Ends that differ: marching tetrahedra put the crossing where the field
                        // is zero. Off the main diagonal, both ends within `step` times half the
                        // edge's length in cells of zero, as a field that changes by `step` a
                        // cell must be to change sign at the midpoint (bear.vm at 97 nodes costs
                        // 4.8% more instructions so; 18% with any of the cell's nodes near zero,
                        // as the main diagonal has it, 9% with both ends within `step`).
                        const double reach = step * (dir == 1 || dir == 2 || dir == 4 ? 0.5 : 0.70710678118654752);
                        if (inside[to] != inside[from] ||
                            (dir != 7 && !(std::fabs(values[from]) <= reach && std::fabs(values[to]) <= reach)))
                            continue;
                        tried[std::size_t(count++)] = uint16_t((x + kLeafCells * (y + kLeafCells * z)) * 8 + dir);
                    }
                }
        if (count == 0) return;
        auto coordinate = [&](int k, int axis) {
            const int c = tried[std::size_t(k)] / 8, dir = tried[std::size_t(k)] % 8;
            const int g = axis == 0 ? c % kLeafCells : axis == 1 ? c / kLeafCells % kLeafCells : c / (kLeafCells * kLeafCells);
            return l_.at(axis, c0[axis] + g) + 0.5 * ((dir >> axis) & 1) * l_.step[axis];
        };
        const double* middle = run_at_points(tape, w.lanes, w.slots, count, coordinate);
        int found = 0;  // those on the other side, moved to the front of `tried`
        for (int k = 0; k < count; ++k) {
            const int c = tried[std::size_t(k)] / 8;
            const bool in = inside[node(c % kLeafCells, c / kLeafCells % kLeafCells, c / (kLeafCells * kLeafCells))];  // as the edge's other end
            if (in ? middle[k] < 0 : middle[k] > 0) tried[std::size_t(found++)] = tried[std::size_t(k)];
        }
        if (found == 0) return;
        // Only a midpoint at least kThinDepth (the main diagonal's) or kThinDepthBetween of a
        // cell beyond the surface (|f| / |∇f|, in dual numbers): a smooth surface's chord of the
        // edge is marching tetrahedra's usual error, not a part left out.
        const Dual* deep = run_at_points(tape, w.dual_lanes, w.dual_slots, found, coordinate);
        const double h = std::max({l_.step[0], l_.step[1], l_.step[2]});
        int last = -1;
        for (int k = 0; k < found; ++k) {
            const Dual& f = deep[k];
            const double slope = std::hypot(f.d[0], f.d[1], f.d[2]);
            const int c = tried[std::size_t(k)] / 8, dir = tried[std::size_t(k)] % 8;
            if (std::fabs(f.v) < (dir == 7 ? kThinDepth : kThinDepthBetween) * h * slope) continue;  // NaN or infinite slope: deep enough
            if (c == last) continue;
            last = c;
            const int x = c % kLeafCells, y = c / kLeafCells % kLeafCells, z = c / (kLeafCells * kLeafCells);
            const uint64_t g[3] = {uint64_t(c0[0] + x), uint64_t(c0[1] + y), uint64_t(c0[2] + z)};
            w.thin_cells.push_back({g[0] + uint64_t(l_.cells[0]) * (g[1] + uint64_t(l_.cells[1]) * g[2]), f.v > 0,
                                    {coordinate(k, 0), coordinate(k, 1), coordinate(k, 2)}});
        }
    }

    /// Each pending edge's zero: Newton's method in t along the edge from the linear guess,
    /// kept inside the bracket [lo, hi] by bisection; batched on the leaf's tape in dual numbers.
    template <class Pending>
    void solve_edges(const Tape& tape, const std::vector<Pending>& pending, LeafMesh& m, bool all_inside,
                     Worker& w) const {
        const std::size_t n = pending.size();
        std::vector<double> t(n), lo(n, 0.0), hi(n, 1.0);
        std::vector<uint8_t> done(n, 0);
        std::vector<Vec> gradient(n, Vec{0, 0, 0});
        std::vector<std::size_t> active;
        for (std::size_t e = 0; e < n; ++e) {
            const auto& p = pending[e];
            // No zero on the edge (the outside end is the domain's border, or the leaf was
            // inside by its intervals): the cap, at the border end.
            if (all_inside || p.f_out > 0) {
                t[e] = 1.0 - kEdgeMargin;
                done[e] = 1;
                continue;
            }
            const double guess = p.f_in / (p.f_in - p.f_out);
            t[e] = std::isfinite(guess) && guess > 0 && guess < 1 ? guess : 0.5;
            active.push_back(e);
        }
        if (!active.empty()) bind_slots(w.dual_lanes, w.dual_slots, tape, kEdgeLanes);
        for (int step = 0; step < kMaxEdgeSteps && !active.empty(); ++step) {
            std::vector<std::size_t> next;
            for (std::size_t first = 0; first < active.size(); first += kEdgeLanes) {
                const int lanes = int(std::min<std::size_t>(kEdgeLanes, active.size() - first));
                for (auto [slot, axis] : tape.arguments)
                    for (int l = 0; l < lanes; ++l) {
                        const auto& p = pending[active[first + l]];
                        w.dual_slots[slot][l] =
                            Dual::variable(p.from[axis] + t[active[first + l]] * p.along[axis], axis);
                    }
                for (auto [slot, value] : tape.constants) std::fill_n(w.dual_slots[slot], lanes, Dual(value));
                run_lanes<Dual, 0>(tape.code.data(), tape.code.size(), w.dual_slots.data(), lanes);
                w.stats.edge_evaluations += lanes;
                Dual* f = w.dual_slots[tape.root_slot];
                // A zero inside the solid along an edge only where the edge ends on a zero (lies
                // in a plane of them); elsewhere Newton lands on exact zeros of the surface.
                const auto ends_on_zero = [&](int l) { return pending[active[first + std::size_t(l)]].zero_end; };
                w.stats.edge_evaluations += read_beside(f, lanes, w.nudged_dual_lanes, w.nudged_dual_slots, ends_on_zero, [&](int l) {
                    const auto& p = pending[active[first + std::size_t(l)]];
                    const double s = t[active[first + std::size_t(l)]];
                    return Vec{p.from[0] + s * p.along[0], p.from[1] + s * p.along[1], p.from[2] + s * p.along[2]};
                }, [&](int l) { return zero_probe_toward(pending[active[first + std::size_t(l)]].along); });
                for (int l = 0; l < lanes; ++l) {
                    const std::size_t e = active[first + l];
                    const auto& p = pending[e];
                    const double value = f[l].v;
                    if (std::isfinite(f[l].d[0]) && std::isfinite(f[l].d[1]) && std::isfinite(f[l].d[2]))
                        gradient[e] = {f[l].d[0], f[l].d[1], f[l].d[2]};
                    if (value == 0) continue;  // exactly on the surface
                    (value > 0 ? lo[e] : hi[e]) = t[e];
                    const double slope =
                        f[l].d[0] * p.along[0] + f[l].d[1] * p.along[1] + f[l].d[2] * p.along[2];
                    const double newton = t[e] - value / slope;
                    double moved;
                    if (std::isfinite(value) && std::isfinite(newton) && newton > lo[e] && newton < hi[e]) {
                        moved = std::fabs(newton - t[e]);
                        t[e] = newton;
                    } else {
                        t[e] = (lo[e] + hi[e]) / 2;
                        moved = hi[e] - lo[e];
                    }
                    if (moved > kEdgeTolerance) next.push_back(e);
                }
            }
            active = std::move(next);
        }
        m.positions.resize(n);
        m.normals.resize(n);
        for (std::size_t e = 0; e < n; ++e) {
            const auto& p = pending[e];
            const double s = std::clamp(t[e], kEdgeMargin, 1.0 - kEdgeMargin);
            for (int a = 0; a < 3; ++a) m.positions[e][a] = p.from[a] + s * p.along[a];
            const double len = std::hypot(gradient[e][0], gradient[e][1], gradient[e][2]);
            m.normals[e] = len > 0 ? Vec{-gradient[e][0] / len, -gradient[e][1] / len, -gradient[e][2] / len}
                                   : Vec{0, 0, 0};
        }
        w.stats.crossing_edges += n;
    }

    /// The reference of a tetrahedron edge of cell (x, y, z) of a leaf.
    static EdgeRef edge_ref(int x, int y, int z, CaseEdge e) {
        const int lower = e.inside & e.outside, dir = e.inside ^ e.outside;
        int u[3] = {x + (lower & 1), y + ((lower >> 1) & 1), z + (lower >> 2)};
        int owner = 0;
        for (int a = 0; a < 3; ++a)
            if (u[a] == kLeafCells) owner |= 1 << a, u[a] = 0;
        return EdgeRef(owner << 12 | ((u[0] + kLeafCells * u[1] + kLeafCells * kLeafCells * u[2]) * 8 + dir));
    }

    /// Each NaN among values[0, count) (of the points position(i)) replaced by the field
    /// kNudge beside its point, and each zero that zero_may_be_inside(i) and that is inside
    /// the solid (zero_inside, mesh_features.hpp) by the least positive value round it. On the
    /// whole model's tape, which every leaf shares: a leaf's shortened tape holds only inside
    /// its box, and the leaves either side of a node must agree on its sign. along_probe(i):
    /// the probe along the edge point i lies on, or −1 (a node). Returns the points evaluated.
    template <class T, class MayBeInside, class Position, class AlongProbe>
    std::size_t read_beside(T* values, int count, std::vector<T>& lanes, std::vector<T*>& slots,
                            const MayBeInside& zero_may_be_inside, const Position& position,
                            const AlongProbe& along_probe) const {
        auto value = [](const T& v) {
            if constexpr (std::is_same_v<T, Dual>) return v.v;
            else return v;
        };
        bool any = false;  // a scan the compiler vectorises: NaN and zeros are rare
        for (int i = 0; i < count; ++i) any |= (value(values[i]) != value(values[i])) | (value(values[i]) == 0);
        if (!any) return 0;
        std::vector<int> points;  // NaN: one lane, beside it; zero: kZeroProbes, round it
        std::vector<Vec> offsets;  // in cells
        for (int i = 0; i < count; ++i) {
            const double v = value(values[i]);
            if (std::isnan(v)) points.push_back(i), offsets.push_back({kNudgeFraction * kNudge[0], kNudgeFraction * kNudge[1], kNudgeFraction * kNudge[2]});
            if (v == 0 && zero_may_be_inside(i))
                for (int k = 0; k < kZeroProbes; ++k) points.push_back(i), offsets.push_back(zero_probe(k));
        }
        if (points.empty()) return 0;
        const int n = int(points.size());
        const T* beside = run_at_points(whole_, lanes, slots, n, [&](int k, int axis) {
            return position(points[std::size_t(k)])[std::size_t(axis)] + offsets[std::size_t(k)][std::size_t(axis)] * l_.step[axis];
        });
        for (int k = 0; k < n;) {
            T& v = values[points[std::size_t(k)]];
            if (value(v) != 0) {  // a NaN
                v = beside[k++];
                continue;
            }
            double probes[kZeroProbes];
            int least = k, lowest = k;
            for (int j = 0; j < kZeroProbes; ++j) {
                probes[j] = value(beside[k + j]);
                if (probes[j] > 0 && (value(beside[least]) <= 0 || probes[j] < value(beside[least]))) least = k + j;
                if (probes[j] < value(beside[lowest])) lowest = k + j;
            }
            if (zero_inside(probes)) v = beside[least];
            // An edge solve's point on a face of the solid that the edge lies in, zero along it
            // (Chainik's wall top at z = 3, beside the lid joined on the rest of that plane):
            // the edge enters the face where the zeros stop being inside, so the point counts
            // as outside and the solve goes on to there, the crease, instead of ending on the
            // first zero it lands on.
            else if (const int d = along_probe(points[std::size_t(k)]);
                     d >= 0 && value(beside[lowest]) < 0 && zero_both_ways(probes, d))
                v = beside[lowest];
            k += kZeroProbes;
        }
        return std::size_t(n);
    }

    // ---- Refinement where a part is thinner than a cell (mesh_refine.hpp) ---------------------

    /// The centre of a cell by its lattice index, x + cells_x·(y + cells_y·z).
    std::array<double, 3> cell_centre(uint64_t cell) const {
        const uint64_t g[3] = {cell % uint64_t(l_.cells[0]), cell / uint64_t(l_.cells[0]) % uint64_t(l_.cells[1]),
                               cell / (uint64_t(l_.cells[0]) * uint64_t(l_.cells[1]))};
        std::array<double, 3> centre;
        for (int a = 0; a < 3; ++a) centre[std::size_t(a)] = l_.at(a, int(g[a])) + 0.5 * l_.step[a];
        return centre;
    }

    /// A fine point's position: bit for bit the lattice's node where it is one.
    Vec fine_position(const FinePoint& p) const {
        Vec out;
        for (int a = 0; a < 3; ++a) {
            const int i = int(p[std::size_t(a)] / kRefine), j = int(p[std::size_t(a)] % kRefine);
            out[std::size_t(a)] = j == 0 ? l_.at(a, i) : l_.at(a, i) + double(j) * (l_.step[a] / kRefine);
        }
        return out;
    }
    /// On the domain's faces: outside, as the lattice's outer nodes are (the caps close the solid).
    bool fine_on_border(const FinePoint& p) const {
        for (int a = 0; a < 3; ++a)
            if (p[std::size_t(a)] == 0 || p[std::size_t(a)] == int64_t(l_.cells[a]) * kRefine) return true;
        return false;
    }

    struct FineValue {
        double evaluated, value;  ///< as evaluated, and after read_beside
        bool inside;
    };
    /// The fine points' values by fine_key: open addressing with linear probing, two arrays
    /// for up to half a million points, not an allocation per point.
    class FineValues {
    public:
        /// The value slot of `key`, made empty if new (`added` says which).
        FineValue& slot(uint64_t key, bool& added) {
            if ((size_ + 1) * 2 > keys_.size()) grow();
            std::size_t i = home(key);
            while (keys_[i] != kEmpty && keys_[i] != key) i = (i + 1) & (keys_.size() - 1);
            added = keys_[i] == kEmpty;
            if (added) keys_[i] = key, values_[i] = {}, ++size_;
            return values_[i];
        }
        bool add(uint64_t key) {
            bool added = false;
            slot(key, added);
            return added;
        }
        const FineValue& at(uint64_t key) const {
            std::size_t i = home(key);
            while (keys_[i] != key) {
                if (keys_[i] == kEmpty) throw std::logic_error("mesher: a fine point was not evaluated");
                i = (i + 1) & (keys_.size() - 1);
            }
            return values_[i];
        }

    private:
        static constexpr uint64_t kEmpty = UINT64_MAX;  ///< no fine_key: its coordinates are below 2^21
        std::size_t home(uint64_t key) const { return std::size_t((key * 0x9e3779b97f4a7c15ULL) >> 20) & (keys_.size() - 1); }
        void grow() {
            std::vector<uint64_t> keys(std::max<std::size_t>(1024, keys_.size() * 2), kEmpty);
            std::vector<FineValue> values(keys.size());
            keys.swap(keys_);
            values.swap(values_);
            size_ = 0;
            for (std::size_t i = 0; i < keys.size(); ++i)
                if (keys[i] != kEmpty) {
                    bool added = false;
                    slot(keys[i], added) = values[i];
                }
        }
        std::vector<uint64_t> keys_;
        std::vector<FineValue> values_;
        std::size_t size_ = 0;
    };

    /// The leaf (of kLeafCells³ cells) a fine point or cell is in, numbered x + leaves_x·(y +
    /// leaves_y·z); a point on the lattice's upper faces in the last.
    uint64_t leaf_of(const FinePoint& p) const {
        uint64_t id = 0;
        for (int a = 2; a >= 0; --a) {
            const int64_t leaf = std::min<int64_t>(p[std::size_t(a)] / (int64_t(kRefine) * kLeafCells), l_.leaves[a] - 1);
            id = id * uint64_t(l_.leaves[a]) + uint64_t(leaf);
        }
        return id;
    }
    /// The model's tape shortened for leaf `leaf` (its values bit for bit: box_simplify.hpp)
    /// in max-live slots, into w.leaf_tape: a refined leaf's points run a few dozen
    /// instructions of bear.vm's thousands.
    const Tape& tape_for_leaf(uint64_t leaf, Worker& w) const {
        const uint64_t c[3] = {leaf % uint64_t(l_.leaves[0]), leaf / uint64_t(l_.leaves[0]) % uint64_t(l_.leaves[1]),
                               leaf / (uint64_t(l_.leaves[0]) * uint64_t(l_.leaves[1]))};
        std::array<Interval, 3> axes;
        for (int a = 0; a < 3; ++a) {
            const int c0 = int(c[a]) * kLeafCells, c1 = std::min(c0 + kLeafCells, l_.cells[a]);
            axes[std::size_t(a)] = {std::min(l_.at(a, c0), l_.at(a, c1)), std::max(l_.at(a, c0), l_.at(a, c1)), false};
        }
        evaluate_intervals(ssa_, axes, w.ranges);
        if (w.tapes.empty()) w.tapes.push_back(std::make_unique<Tape>());
        simplify_for_sign(ssa_, w.ranges, w.box, *w.tapes[0], /*keep_values=*/true);
        reallocate_slots(*w.tapes[0], w.leaf_tape, w.slot_scratch);
        return w.leaf_tape;
    }
    /// Calls work(group, tape, worker) for each run of `items` (sorted by their leaf,
    /// leaf_of_item) in one leaf, on the workers, with that leaf's tape.
    template <class Work, class LeafOf>
    void per_leaf(std::size_t count, const LeafOf& leaf_of_item, std::vector<Worker>& workers, const EvalOptions& options,
                  const Work& work) const {
        std::vector<std::size_t> starts;
        for (std::size_t i = 0; i < count; ++i)
            if (i == 0 || leaf_of_item(i) != leaf_of_item(i - 1)) starts.push_back(i);
        starts.push_back(count);
        EvalOptions quiet = options;
        quiet.progress = nullptr;
        parallel_for(starts.size() - 1, quiet, [&](std::size_t g, int worker) {
            Worker& w = workers[std::size_t(worker)];
            const Tape& tape = tape_for_leaf(leaf_of_item(starts[g]), w);
            work(starts[g], starts[g + 1], tape, w);
            return std::size_t{0};
        });
    }

    /// Evaluates the points `keys` names (none in `values` yet, no two the same) into
    /// `values`, on their leaves' tapes, NaN and zeros read beside as at the lattice's nodes
    /// (so a coarse node gets the sign its leaf gave it).
    void evaluate_fine(std::vector<uint64_t> keys, FineValues& values, std::vector<Worker>& workers,
                       const EvalOptions& options) const {
        constexpr std::size_t kBatch = 1024;
        std::sort(keys.begin(), keys.end(), [&](uint64_t a, uint64_t b) {
            return std::pair(leaf_of(fine_point(a)), a) < std::pair(leaf_of(fine_point(b)), b);
        });
        std::vector<FineValue> out(keys.size());
        per_leaf(keys.size(), [&](std::size_t i) { return leaf_of(fine_point(keys[i])); }, workers, options,
                 [&](std::size_t begin, std::size_t end, const Tape& tape, Worker& w) {
            for (std::size_t first = begin; first < end; first += kBatch) {
                const int n = int(std::min(kBatch, end - first));
                auto position = [&](int i) { return fine_position(fine_point(keys[first + std::size_t(i)])); };
                double evaluated[kBatch], value[kBatch];
                std::copy_n(run_at_points(tape, w.lanes, w.slots, n, [&](int i, int axis) { return position(i)[std::size_t(axis)]; }), n,
                            evaluated);
                std::copy_n(evaluated, n, value);
                w.stats.node_evaluations += std::size_t(n);
                w.stats.node_evaluations += read_beside(value, n, w.nudged_lanes, w.nudged_slots, [](int) { return true; },
                                                        position, [](int) { return -1; });
                for (int i = 0; i < n; ++i)
                    out[first + std::size_t(i)] = {evaluated[i], value[i], !fine_on_border(fine_point(keys[first + std::size_t(i)])) && value[i] > 0};
            }
        });
        for (std::size_t i = 0; i < keys.size(); ++i) {
            bool added = false;
            values.slot(keys[i], added) = out[i];
        }
    }

    /// The cells to refine: the thin cells, and each cell across a face of a refined one whose
    /// fine nodes show a part its four corners do not (all on one side, a fine node on the
    /// other: the blade or sheet goes on into it), until none is left or kMaxRefinedCells.
    RefinedCells cells_to_refine(const std::vector<uint64_t>& thin, const std::vector<uint64_t>& keep, FineValues& values,
                                 std::vector<Worker>& workers, const EvalOptions& options, std::vector<uint64_t>& left) const {
        RefinedCells region({l_.cells[0], l_.cells[1], l_.cells[2]});
        std::vector<uint64_t> frontier, dropped;  // dropped: wanted beyond kMaxRefinedCells
        for (uint64_t cell : thin)
            if (!region.would_change(cell, keep)) frontier.push_back(cell);
        while (!frontier.empty()) {
            if (region.size() + frontier.size() > kMaxRefinedCells) {
                dropped.assign(frontier.begin() + long(kMaxRefinedCells - region.size()), frontier.end());
                frontier.resize(kMaxRefinedCells - region.size());
            }
            region.refine(frontier);
            std::vector<uint64_t> keys;
            for (uint64_t cell : frontier)
                for (const FinePoint& p : region.nodes_of(cell))
                    if (values.add(fine_key(p))) keys.push_back(fine_key(p));
            evaluate_fine(keys, values, workers, options);
            std::vector<uint64_t> next;
            for (uint64_t cell : frontier) {
                const auto c = region.coords(cell);
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side) {
                        std::array<int64_t, 3> across = c;
                        across[std::size_t(axis)] += side ? 1 : -1;
                        const uint64_t neighbour = region.cell_at(across);
                        if (neighbour == UINT64_MAX || region.refined(neighbour)) continue;
                        const int b = (axis + 1) % 3, d = (axis + 2) % 3;
                        auto inside_at = [&](int i, int j) {
                            FinePoint p{c[0] * kRefine, c[1] * kRefine, c[2] * kRefine};
                            p[std::size_t(axis)] += side * kRefine;
                            p[std::size_t(b)] += i;
                            p[std::size_t(d)] += j;
                            return values.at(fine_key(p)).inside;
                        };
                        const bool corner = inside_at(0, 0);
                        if (inside_at(kRefine, 0) != corner || inside_at(0, kRefine) != corner || inside_at(kRefine, kRefine) != corner)
                            continue;  // the surface crosses the face's corners: the lattice sees it
                        bool other = false;
                        for (int i = 0; i <= kRefine && !other; ++i)
                            for (int j = 0; j <= kRefine && !other; ++j) other = inside_at(i, j) != corner;
                        if (other) next.push_back(neighbour);
                    }
            }
            std::sort(next.begin(), next.end());
            next.erase(std::unique(next.begin(), next.end()), next.end());
            std::erase_if(next, [&](uint64_t cell) { return region.refined(cell) || region.would_change(cell, keep); });
            if (region.size() >= kMaxRefinedCells) {
                dropped.insert(dropped.end(), next.begin(), next.end());
                break;
            }
            frontier = std::move(next);
        }
        std::sort(dropped.begin(), dropped.end());
        dropped.erase(std::unique(dropped.begin(), dropped.end()), dropped.end());
        left = std::move(dropped);
        return region;
    }

    /// Refines the `seeds` (sorted) and the cells their thin parts go on into, but none that
    /// would change a cell of `keep` (sorted: RefineQuery), and replaces the triangles of every
    /// cell whose tetrahedra change with marching tetrahedra on the new ones. Returns the
    /// refined cells (sorted), which the sharp-feature pass then leaves as they are.
    /// `vertex_edges`: each mesh vertex's lattice edge (weld), or UINT64_MAX, kept up to date:
    /// a second call with more seeds redoes the first's cells.
    std::vector<uint64_t> refine(const std::vector<uint64_t>& seeds, const std::vector<uint64_t>& keep, Mesh& mesh,
                                 std::vector<uint64_t>& triangle_cells,
                                 std::vector<uint64_t>& vertex_edges, MeshStats& stats, const EvalOptions& options) const {
        std::vector<Worker> workers(std::size_t(resolve_threads(options.threads)));
        FineValues values;
        std::vector<uint64_t> left;
        const RefinedCells region = cells_to_refine(seeds, keep, values, workers, options, left);
        stats.refinement_left = left.size();
        if (!left.empty()) stats.first_left = cell_centre(left.front());
        const std::vector<uint64_t> changed = region.changed_cells();
        stats.refined_cells = region.size();
        stats.transition_cells = changed.size() - region.size();
        std::vector<std::array<FinePoint, 4>> tets;  // one cell's at a time
        {
            std::vector<uint64_t> keys;
            for (uint64_t cell : changed) {
                tets.clear();
                region.tetrahedra(cell, tets);
                for (const auto& t : tets)
                    for (const FinePoint& p : t)
                        if (values.add(fine_key(p))) keys.push_back(fine_key(p));
            }
            evaluate_fine(keys, values, workers, options);
        }
        // The lattice's edges keep the vertices their leaves gave them (the cells beyond share
        // them). Only edges of changed cells are looked up, and each has its lower end at one of
        // their corners: the vertices on others are passed over on the threads (a map of every
        // vertex cost bear.vm at 257 nodes 64 ms, serial).
        std::vector<uint64_t> corners;
        for (uint64_t cell : changed) {
            const auto c = region.coords(cell);
            for (int k = 0; k < 8; ++k)
                corners.push_back(uint64_t(c[0] + (k & 1)) +
                                  uint64_t(l_.nodes[0]) * (uint64_t(c[1] + (k >> 1 & 1)) + uint64_t(l_.nodes[1]) * uint64_t(c[2] + (k >> 2))));
        }
        std::sort(corners.begin(), corners.end());
        corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        std::vector<char> at_corner(vertex_edges.size());
        EvalOptions quiet = options;
        quiet.progress = nullptr;
        parallel_ranges(vertex_edges.size(), 4096, quiet, [&](std::size_t begin, std::size_t end, int) {
            for (std::size_t v = begin; v < end; ++v)
                at_corner[v] = vertex_edges[v] != UINT64_MAX && std::binary_search(corners.begin(), corners.end(), vertex_edges[v] / 8);
        });
        std::unordered_map<uint64_t, uint32_t> on_lattice;
        for (uint32_t v = 0; v < vertex_edges.size(); ++v)
            if (at_corner[v]) on_lattice.emplace(vertex_edges[v], v);
        auto lattice_edge = [&](const FinePoint& p, const FinePoint& q) -> uint64_t {
            uint64_t lower[3];
            int dir = 0;
            for (int a = 0; a < 3; ++a) {
                if (p[std::size_t(a)] % kRefine != 0 || q[std::size_t(a)] % kRefine != 0) return UINT64_MAX;
                const int64_t i = p[std::size_t(a)] / kRefine, j = q[std::size_t(a)] / kRefine;
                if (i != j) dir |= 1 << a;
                lower[a] = uint64_t(std::min(i, j));
            }
            return (lower[0] + uint64_t(l_.nodes[0]) * (lower[1] + uint64_t(l_.nodes[1]) * lower[2])) * 8 + uint64_t(dir);
        };
        struct NewEdge {
            Vec from, along;
            double f_in, f_out;
            bool zero_end;
        };
        std::vector<NewEdge> pending;
        std::vector<uint64_t> pending_leaf;  // the leaf of the cell each was found in
        struct PairHash {
            std::size_t operator()(const std::pair<uint64_t, uint64_t>& p) const { return std::hash<uint64_t>()(p.first * 0x9e3779b97f4a7c15ULL ^ p.second); }
        };
        std::unordered_map<std::pair<uint64_t, uint64_t>, uint32_t, PairHash> new_edges;  // (inside, outside) → pending index
        const uint32_t base = uint32_t(mesh.vertices.size());
        uint64_t leaf = 0;  // the leaf of the cell whose triangles are being made
        auto vertex = [&](const FinePoint& in, const FinePoint& out) -> uint32_t {
            if (const uint64_t e = lattice_edge(in, out); e != UINT64_MAX)
                if (const auto it = on_lattice.find(e); it != on_lattice.end()) return it->second;
            const std::pair<uint64_t, uint64_t> key{fine_key(in), fine_key(out)};
            if (const auto it = new_edges.find(key); it != new_edges.end()) return base + it->second;
            const FineValue& a = values.at(key.first);
            const FineValue& b = values.at(key.second);
            const Vec p = fine_position(in), q = fine_position(out);
            pending.push_back({p, {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, a.value, b.value, a.evaluated == 0 || b.value == 0});
            pending_leaf.push_back(leaf);
            new_edges.emplace(key, uint32_t(pending.size() - 1));
            return base + uint32_t(pending.size() - 1);
        };
        std::vector<std::array<uint32_t, 3>> triangles;
        std::vector<uint64_t> cells_of;
        for (uint64_t cell : changed) {
            tets.clear();
            region.tetrahedra(cell, tets);
            const auto c = region.coords(cell);
            leaf = leaf_of({c[0] * kRefine, c[1] * kRefine, c[2] * kRefine});
            for (const auto& q : tets) {
                int inside = 0;
                std::array<Vec, 4> corner;  // in the fine lattice's coordinates: the sides are the same
                for (int k = 0; k < 4; ++k) {
                    inside |= int(values.at(fine_key(q[std::size_t(k)])).inside) << k;
                    for (int a = 0; a < 3; ++a) corner[std::size_t(k)][std::size_t(a)] = double(q[std::size_t(k)][std::size_t(a)]);
                }
                TetTriangle tri[2];
                const int count = tetrahedron_triangles(corner, inside, tri);
                for (int k = 0; k < count; ++k) {
                    std::array<uint32_t, 3> out;
                    for (int v = 0; v < 3; ++v)
                        out[std::size_t(v)] = vertex(q[std::size_t(tri[k][std::size_t(v)][0])], q[std::size_t(tri[k][std::size_t(v)][1])]);
                    triangles.push_back(out);
                    cells_of.push_back(cell);
                }
            }
        }
        // The new edges' zeros, leaf by leaf on the leaves' tapes (an edge lies in its cell's
        // closed box, so in its leaf's).
        std::vector<uint32_t> order(pending.size());
        for (uint32_t e = 0; e < order.size(); ++e) order[e] = e;
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return pending_leaf[a] < pending_leaf[b]; });
        mesh.vertices.resize(base + pending.size());
        mesh.normals.resize(base + pending.size());
        per_leaf(order.size(), [&](std::size_t i) { return pending_leaf[order[i]]; }, workers, options,
                 [&](std::size_t begin, std::size_t end, const Tape& tape, Worker& w) {
            std::vector<NewEdge> part;
            for (std::size_t i = begin; i < end; ++i) part.push_back(pending[order[i]]);
            LeafMesh solved;
            solve_edges(tape, part, solved, false, w);
            for (std::size_t i = begin; i < end; ++i) {
                mesh.vertices[base + order[i]] = solved.positions[i - begin];
                mesh.normals[base + order[i]] = solved.normals[i - begin];
            }
        });
        vertex_edges.resize(mesh.vertices.size(), UINT64_MAX);
        // The changed cells' old triangles out, the new in, and the vertices left unused dropped.
        std::vector<std::array<uint32_t, 3>> kept;
        std::vector<uint64_t> kept_cells;
        kept.reserve(mesh.triangles.size() + triangles.size());
        kept_cells.reserve(mesh.triangles.size() + triangles.size());
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
            if (!std::binary_search(changed.begin(), changed.end(), triangle_cells[t]))
                kept.push_back(mesh.triangles[t]), kept_cells.push_back(triangle_cells[t]);
        kept.insert(kept.end(), triangles.begin(), triangles.end());
        kept_cells.insert(kept_cells.end(), cells_of.begin(), cells_of.end());
        mesh.triangles = std::move(kept);
        triangle_cells = std::move(kept_cells);
        const std::vector<uint32_t> renumber = drop_unused_vertices(mesh);
        for (std::size_t v = 0; v < renumber.size(); ++v)
            if (renumber[v] != UINT32_MAX) vertex_edges[renumber[v]] = vertex_edges[v];  // renumber[v] <= v
        vertex_edges.resize(mesh.vertices.size());
        for (const Worker& w : workers) {
            stats.node_evaluations += w.stats.node_evaluations;
            stats.edge_evaluations += w.stats.edge_evaluations;
            stats.crossing_edges += w.stats.crossing_edges;
        }
        return region.refined_cells();
    }

private:
    Lattice l_;
    const Tape& ssa_;
    const Tape& whole_;
};

/// Where `edge` is in a leaf's increasing crossing edges: a binary search without branches.
/// Three per triangle were most of the weld, std::lower_bound's branch mispredicting on
/// about half its steps (tanglecube.vm at 512 cells: 35% of a two-thread run).
std::size_t edge_index(const std::vector<uint16_t>& edges, uint16_t edge) {
    if (edges.empty()) throw std::logic_error("mesher: a crossing edge has no vertex");
    const uint16_t* first = edges.data();
    for (std::size_t n = edges.size(); n > 1;) {
        const std::size_t half = n / 2;
        first = first[half] <= edge ? first + half : first;
        n -= half;
    }
    if (*first != edge) throw std::logic_error("mesher: a crossing edge has no vertex");
    return std::size_t(first - edges.data());
}

/// Joins the leaves' vertices (each owned by one leaf) and triangles into one indexed mesh;
/// `triangle_cells` gets each triangle's cell, x + cells_x·(y + cells_y·z), and
/// `vertex_edges`, if given, each vertex's lattice edge, node·8 + direction (node x +
/// nodes_x·(y + nodes_y·z)). Leaves are welded in parallel, each into its own ranges, which
/// depend only on the leaves' order.
Mesh weld(std::vector<LeafMesh>& leaves, const Lattice& l, std::vector<uint64_t>& triangle_cells,
          std::vector<uint64_t>* vertex_edges, const EvalOptions& options) {
    std::sort(leaves.begin(), leaves.end(), [](const LeafMesh& a, const LeafMesh& b) {
        return std::tie(a.leaf[2], a.leaf[1], a.leaf[0]) < std::tie(b.leaf[2], b.leaf[1], b.leaf[0]);
    });
    std::vector<int32_t> leaf_at(std::size_t(l.leaves[0]) * l.leaves[1] * l.leaves[2], -1);
    auto slot = [&](int x, int y, int z) { return (std::size_t(z) * l.leaves[1] + y) * l.leaves[0] + x; };
    std::vector<uint32_t> base(leaves.size() + 1, 0);
    std::vector<std::size_t> first_triangle(leaves.size() + 1, 0);
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        leaf_at[slot(leaves[i].leaf[0], leaves[i].leaf[1], leaves[i].leaf[2])] = int32_t(i);
        const std::size_t next = std::size_t(base[i]) + leaves[i].edges.size();
        if (next > UINT32_MAX) throw std::length_error("the mesh has more than 2^32 vertices");
        base[i + 1] = uint32_t(next);
        if (leaves[i].positions.size() != leaves[i].edges.size() || leaves[i].normals.size() != leaves[i].edges.size() ||
            leaves[i].triangle_cells.size() != leaves[i].triangles.size())
            throw std::logic_error("mesher: a leaf's vertices or triangles differ in number from their edges or cells");
        first_triangle[i + 1] = first_triangle[i] + leaves[i].triangles.size();
    }
    Mesh mesh;
    mesh.vertices.resize(base.back());
    mesh.normals.resize(base.back());
    mesh.triangles.resize(first_triangle.back());
    triangle_cells.resize(first_triangle.back());
    if (vertex_edges) vertex_edges->resize(base.back());
    EvalOptions quiet;
    quiet.threads = options.threads;
    parallel_for(leaves.size(), quiet, [&](std::size_t i, int) {
        const LeafMesh& m = leaves[i];
        std::copy(m.positions.begin(), m.positions.end(), mesh.vertices.begin() + base[i]);
        std::copy(m.normals.begin(), m.normals.end(), mesh.normals.begin() + base[i]);
        if (vertex_edges)
            for (std::size_t k = 0; k < m.edges.size(); ++k) {
                const int node = m.edges[k] >> 3, dir = m.edges[k] & 7;
                const uint64_t x = uint64_t(m.leaf[0]) * kLeafCells + uint64_t(node % kLeafCells),
                               y = uint64_t(m.leaf[1]) * kLeafCells + uint64_t(node / kLeafCells % kLeafCells),
                               z = uint64_t(m.leaf[2]) * kLeafCells + uint64_t(node / (kLeafCells * kLeafCells));
                (*vertex_edges)[base[i] + k] = (x + uint64_t(l.nodes[0]) * (y + uint64_t(l.nodes[1]) * z)) * 8 + uint64_t(dir);
            }
        std::size_t t = first_triangle[i];
        for (const auto& tri : m.triangles) {
            std::array<uint32_t, 3>& out = mesh.triangles[t++];
            for (int v = 0; v < 3; ++v) {
                const int owner = tri[v] >> 12;
                std::size_t at = i;
                if (owner != 0) {
                    const int x = m.leaf[0] + (owner & 1), y = m.leaf[1] + ((owner >> 1) & 1), z = m.leaf[2] + (owner >> 2);
                    const int32_t found = x < l.leaves[0] && y < l.leaves[1] && z < l.leaves[2] ? leaf_at[slot(x, y, z)] : -1;
                    if (found < 0) throw std::logic_error("mesher: a crossing edge's owner leaf was not meshed");
                    at = std::size_t(found);
                }
                out[v] = base[at] + uint32_t(edge_index(leaves[at].edges, uint16_t(tri[v] & 0xfff)));
            }
        }
        t = first_triangle[i];
        for (uint16_t local : m.triangle_cells) {
            const uint64_t x = uint64_t(m.leaf[0]) * kLeafCells + local % kLeafCells,
                           y = uint64_t(m.leaf[1]) * kLeafCells + local / kLeafCells % kLeafCells,
                           z = uint64_t(m.leaf[2]) * kLeafCells + local / (kLeafCells * kLeafCells);
            triangle_cells[t++] = x + uint64_t(l.cells[0]) * (y + uint64_t(l.cells[1]) * z);
        }
        return std::size_t{0};
    });
    // Normals where the gradient is not defined (caps on the domain's border, corners of
    // sqrt(a² + b²)): the area-weighted normal of the triangles around the vertex.
    std::vector<Vec> fallback;
    for (const auto& t : mesh.triangles) {
        bool missing = false;
        for (uint32_t v : t) missing |= mesh.normals[v] == Vec{0, 0, 0};
        if (!missing) continue;
        if (fallback.empty()) fallback.assign(mesh.vertices.size(), Vec{0, 0, 0});
        const Vec& a = mesh.vertices[t[0]];
        const Vec& b = mesh.vertices[t[1]];
        const Vec& c = mesh.vertices[t[2]];
        const Vec u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const Vec n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        for (uint32_t v : t)
            for (int k = 0; k < 3; ++k) fallback[v][k] += n[k];
    }
    if (!fallback.empty())
        for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
            if (mesh.normals[v] == Vec{0, 0, 0}) {
                const double len = std::hypot(fallback[v][0], fallback[v][1], fallback[v][2]);
                if (len > 0) mesh.normals[v] = {fallback[v][0] / len, fallback[v][1] / len, fallback[v][2] / len};
            }
    return mesh;
}

}  // namespace

Mesh extract_mesh(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                  MeshStats* stats) {
    if (grid.dims != 3) throw std::invalid_argument("a mesh needs a 3D model (X, Y, Z)");
    if (grid.x.nodes < 2 || grid.y.nodes < 2 || grid.z.nodes < 2)
        throw std::invalid_argument("a mesh needs at least 2 grid nodes along each axis");
    const auto pruning = std::make_shared<const Tape>(pruning_tape(graph, root));
    Tape whole;
    SlotScratch whole_scratch;
    reallocate_slots(*pruning, whole, whole_scratch);
    const Mesher mesher(grid, *pruning, whole);
    const Lattice& l = mesher.lattice();
    int size = 1;
    while (size < std::max({l.leaves[0], l.leaves[1], l.leaves[2]})) size *= 2;

    const int threads = resolve_threads(options.threads);
    std::vector<Worker> workers(threads);
    struct Item {
        Mesher::Box box;
        std::shared_ptr<const Tape> tape;
    };
    std::vector<Item> items{{Mesher::Box{{0, 0, 0}, size}, pruning}};
    // Breadth-first until there are enough boxes to share, then depth-first per worker.
    const std::size_t enough = std::size_t(32) * threads;
    while (items.size() < enough && !items.empty() && items.front().box.size > 1) {
        std::vector<std::vector<Item>> children(items.size());
        EvalOptions quiet = options;
        quiet.progress = nullptr;
        parallel_for(items.size(), quiet, [&](std::size_t i, int worker) {
            auto simplified = std::make_shared<Tape>();
            bool all_inside = false;
            if (mesher.decide(items[i].box, *items[i].tape, workers[worker], *simplified, all_inside) ==
                Mesher::Verdict::Empty)
                return std::size_t{0};
            // A tape the box barely shortens is not copied: the parent's serves the children
            // too, so a model no box simplifies keeps one tape, not one per box.
            std::shared_ptr<const Tape> tape = simplified;
            if (simplified->code.size() * 8 > items[i].tape->code.size() * 7) tape = items[i].tape;
            for (const Mesher::Box& child : mesher.split(items[i].box)) children[i].push_back({child, tape});
            return std::size_t{0};
        });
        std::vector<Item> next;
        for (auto& c : children) next.insert(next.end(), c.begin(), c.end());
        items = std::move(next);
    }
    parallel_for(items.size(), options, [&](std::size_t i, int worker) {
        mesher.walk(items[i].box, *items[i].tape, workers[worker], 0, options.cancel);
        return std::size_t{0};
    });
    if (options.cancel && options.cancel->load()) return {};
    std::vector<LeafMesh> leaves;
    MeshStats total;
    std::vector<ThinPart> thin;
    DomainCaps caps;
    caps.margin = kEdgeMargin;
    for (Worker& w : workers) {
        for (std::size_t f = 0; f < 6; ++f) caps.faces[f] = caps.faces[f] || w.cut_faces[f];
        std::move(w.leaves.begin(), w.leaves.end(), std::back_inserter(leaves));
        total.boxes += w.stats.boxes;
        total.leaves += w.stats.leaves;
        total.node_evaluations += w.stats.node_evaluations;
        total.edge_evaluations += w.stats.edge_evaluations;
        total.crossing_edges += w.stats.crossing_edges;
        thin.insert(thin.end(), w.thin_cells.begin(), w.thin_cells.end());
    }
    std::sort(thin.begin(), thin.end());  // the same on any number of threads
    total.thin_cells = thin.size();
    if (!thin.empty()) total.first_thin = mesher.cell_centre(thin[0].cell);
    const bool refining = RefinedCells::fits({l.cells[0], l.cells[1], l.cells[2]});
    if (!refining && !thin.empty()) {  // a lattice over half a million cells long: none refined, said
        total.refinement_left = thin.size();
        total.first_left = total.first_thin;
    }
    workers.clear();
    std::vector<uint64_t> triangle_cells, vertex_edges;
    Mesh mesh = weld(leaves, l, triangle_cells, refining ? &vertex_edges : nullptr, options);
    leaves.clear();
    if (options.cancel && options.cancel->load()) return {};
    // The feature pass says which cells to refine: the thin cells where it did not put an
    // edge back, and those round edges it left more than half a cell off (wedges thinner than
    // a cell that no centre fell in). They are refined and the pass runs again on the new
    // mesh, up to kRefinePasses times.
    std::vector<uint64_t> seeds, keep, refined;
    std::vector<std::array<double, 3>> crossings_left;
    for (int pass = 0;; ++pass) {
        RefineQuery query;
        query.thin = thin;
        const bool last = !refining || pass == kRefinePasses;
        if (sharpen_features(graph, root, grid, mesh, triangle_cells, caps, refined, stats ? &total.features : nullptr,
                             last ? nullptr : &query, &crossings_left))
            break;
        if (options.cancel && options.cancel->load()) return {};
        const std::size_t before = seeds.size();
        seeds.insert(seeds.end(), query.refine.begin(), query.refine.end());
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        keep.insert(keep.end(), query.keep.begin(), query.keep.end());
        std::sort(keep.begin(), keep.end());
        keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
        if (seeds.size() == before) {  // nothing new to refine: the next pass is the last
            pass = kRefinePasses - 1;
            continue;
        }
        total.refine_seeds = seeds.size();
        refined = mesher.refine(seeds, keep, mesh, triangle_cells, vertex_edges, total, options);
        if (options.cancel && options.cancel->load()) return {};  // its points may be half evaluated
    }
    // Last, on the finished mesh: the surface it passes far from, and the edges' crossings the
    // feature pass left off it (mesh_cover.hpp), which it then counts as the finished mesh
    // has them.
    cover_surface(graph, root, grid, mesh, options, crossings_left, &total.cover);
    if (options.cancel && options.cancel->load()) return {};
    if (stats) *stats = total;
    return mesh;
}

}  // namespace fortu
