// interp/mesh_features.cpp — seeds, edge curves traced cell to cell, their face crossings and
// corners, and the cells re-triangulated through them (the why is in mesh_features.hpp).
#include "interp/mesh_features.hpp"

#include "interp/lane_kernel.hpp"
#include "interp/segment_through_triangle.hpp"
#include "interp/tape.hpp"
#include "interp/written_r_operations.hpp"
#include "runtime/mesh_compare.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace fortu {
namespace {

using Vec = std::array<double, 3>;
using Tri = std::array<uint32_t, 3>;

/// The index of the boundary segment {a, b} (either way round) in the closed `loop`, or
/// loop.size() when it is not one of its segments.
std::size_t segment_index(const std::vector<uint32_t>& loop, std::pair<uint32_t, uint32_t> segment) {
    const std::size_t n = loop.size();
    std::size_t at = n;
    for (std::size_t i = 0; i < n; ++i)
        if (std::pair{std::min(loop[i], loop[(i + 1) % n]), std::max(loop[i], loop[(i + 1) % n])} == segment) at = i;
    return at;
}

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
Vec midpoint(const Vec& a, const Vec& b) { return {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2}; }
bool finite(const Vec& a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

/// A cell is tested when two of its vertex normals are more than ~26° apart: at 128 cells a
/// smooth surface bends that much in a cell only where it is nearly singular itself.
constexpr double kFeatureCosine = 0.9;
/// An operand counts as vanishing in a cell when its first-order estimate reaches zero
/// within twice the cell's half diagonal (curved operands reach a little further).
constexpr double kReachFactor = 2.0;
/// A new triangle's area, in cell², at least: STL's float32 rounding (6e-8 relative) must
/// not make it degenerate, nor flip its projection. Not more: a corner 1/50 of a cell past a
/// grid plane has a fan with triangles of 6e-5 cell² (the FLOZ3 plate on 16 nodes).
constexpr double kMinArea = 1e-5;
constexpr double kMinProjectedArea = 1e-6;
/// The same bounds for the triangles of a cell an edge crosses: an edge that passes within
/// 1e-4 cell of a grid edge (it happens: the Steinmetz curve on a lattice of 33) leaves only
/// slivers of about 1e-8 cell² there, still 100 times the independent checker's 1e-10.
constexpr double kMinChainArea = 1e-9;
constexpr double kMinChainProjectedArea = 1e-11;
/// A new triangle's centroid, in cells, at most this far from the surface (first order:
/// |f| / |∇f| there): half a cell, the mesh's bound on smooth parts. Why: its vertices are on
/// the surface, but a polygon joined over several cells (a wedge's, around an acute edge or a
/// tip) can give triangles five cells long whose middle is a cell or more away where the
/// surface curves (bear.vm at 128 nodes: 1.4 cells).
constexpr double kMaxCentroidDistance = 0.5;
/// The same for a band's strips (build_band), at their centroids and edge midpoints, in
/// cells: half the bound above, as the first-order estimate falls short of the distance
/// where the surface curves (the pawn's collar at 41 nodes: 0.5 estimated, 0.516 measured).
/// Also the middle of a joined triangle longer than two cells (triangle_near_surface).
constexpr double kMaxBandDistance = 0.25;
/// Newton's method stops when a step is below this fraction of a cell; the point is then
/// on the feature to round-off (quadratic convergence, one step for planes).
constexpr double kStepTolerance = 1e-13;
/// Halvings toward where an operand's domain ends (solve_feature): a double's 53 bits and
/// some to spare, so the end is found to the last bit.
constexpr int kEndBisections = 64;
/// Newton steps past an end allowed beyond the usual 40: each leaves the point where the
/// end cuts the step (a fifth of it for X^0.2, whose step from X goes to −4X; half for √Y), so
/// the other equations take only that part of their own step and converge linearly there.
constexpr int kMaxEnds = 64;
/// Operands whose gradients make less than ~11° with the span of those already chosen are
/// not independent enough to solve for (a tangency, not an edge).
constexpr double kIndependence = 0.2;

/// The model and every operand of its R-operations (and MIN/MAX, the CSG operations of `.vm`
/// files), with exact gradients, from one run of one tape.
class FeatureField {
public:
    struct Operation {
        int a, b;          ///< indices of its operands in the outputs
        ir::NodeId node;
    };

    FeatureField(const ir::Graph& graph, ir::NodeId root) {
        std::vector<ir::NodeId> outputs{root};
        std::map<ir::NodeId, int> index;
        auto output = [&](ir::NodeId n) {
            const auto [it, fresh] = index.emplace(n, int(outputs.size()));
            if (fresh) outputs.push_back(n);
            return it->second;
        };
        for (ir::NodeId id : graph.reachable(root)) {
            ir::NodeId a, b;
            if (operation(graph, id, a, b)) ops_.push_back({output(a), output(b), id});
        }
        is_operation_.assign(outputs.size(), -1);
        for (std::size_t k = 0; k < ops_.size(); ++k) {
            const auto it = index.find(ops_[k].node);
            if (it != index.end()) is_operation_[it->second] = int(k);
        }
        if (!ops_.empty()) tape_ = compile_tape(graph, TapeSpec{outputs, {}, {}, true});
        values_.resize(tape_.slot_count);
        slots_.resize(tape_.slot_count);
        for (uint32_t s = 0; s < tape_.slot_count; ++s) slots_[s] = &values_[s];
    }

    /// Whether node `id` is an operation with edges (an R-operation, MIN, MAX or R0 written
    /// out), and its operands.
    static bool operation(const ir::Graph& graph, ir::NodeId id, ir::NodeId& a, ir::NodeId& b) {
        const ir::Node& n = graph.node(id);
        a = n.args[0], b = n.args[1];
        return (ir::op_flags(n.op) & ir::kROperation) || n.op == ir::Op::Min || n.op == ir::Op::Max || written_r0(graph, id, a, b);
    }

    const std::vector<Operation>& operations() const { return ops_; }
    /// The operation whose node output `i` is, or -1.
    int operation_of(int i) const { return is_operation_[i]; }

    /// Evaluates everything at p; value(i) and gradient(i) read output i (0: the model).
    void at(const Vec& p) {
        std::fill(values_.begin(), values_.end(), ir::Dual(0.0));
        for (auto [slot, value] : tape_.constants) values_[slot] = ir::Dual(value);
        for (auto [slot, axis] : tape_.arguments) values_[slot] = ir::Dual::variable(p[axis], axis);
        run_lanes<ir::Dual, 1>(tape_.code.data(), tape_.code.size(), slots_.data(), 1);
    }
    double value(int i) const { return values_[tape_.outputs[i]].v; }
    Vec gradient(int i) const {
        const ir::Dual& d = values_[tape_.outputs[i]];
        return {d.d[0], d.d[1], d.d[2]};
    }

private:
    std::vector<Operation> ops_;
    std::vector<int> is_operation_;
    Tape tape_;
    std::vector<ir::Dual> values_;
    std::vector<ir::Dual*> slots_;
};

/// The first `want` of `equations` (outputs of `field`, evaluated) whose gradients are finite
/// and independent of those chosen before them; false if there are fewer.
bool choose_independent(const FeatureField& field, const std::vector<int>& equations, int want,
                        std::vector<int>& chosen) {
    chosen.clear();
    std::vector<Vec> basis;
    for (int e : equations) {
        if (int(chosen.size()) == want) break;
        const Vec g = field.gradient(e);
        const double length = norm(g);
        if (!finite(g) || !(length > 0) || !std::isfinite(field.value(e))) continue;
        Vec r = g;  // the part of g not in the span of the chosen gradients
        for (const Vec& b : basis) {
            const double c = dot(r, b);
            for (int k = 0; k < 3; ++k) r[k] -= c * b[k];
        }
        const double left = norm(r);
        if (left < kIndependence * length) continue;
        basis.push_back({r[0] / left, r[1] / left, r[2] / left});
        chosen.push_back(e);
    }
    return int(chosen.size()) == want;
}

/// The minimum-norm step s = Jᵀ(JJᵀ)⁻¹F for the rows of J and the values F (at most three);
/// false when JJᵀ is singular.
bool min_norm_step(const std::vector<Vec>& rows, const std::vector<double>& rhs, Vec& step) {
    const int n = int(rows.size());
    double m[3][4];
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) m[i][j] = dot(rows[i], rows[j]);
        m[i][3] = rhs[i];
    }
    for (int c = 0; c < n; ++c) {
        int pivot = c;
        for (int r = c + 1; r < n; ++r)
            if (std::fabs(m[r][c]) > std::fabs(m[pivot][c])) pivot = r;
        std::swap(m[c], m[pivot]);
        if (!(std::fabs(m[c][c]) > 0)) return false;
        for (int r = 0; r < n; ++r) {
            if (r == c) continue;
            const double f = m[r][c] / m[c][c];
            for (int k = c; k < 4; ++k) m[r][k] -= f * m[c][k];
        }
    }
    step = {0, 0, 0};
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) step[k] += m[i][3] / m[i][i] * rows[i][k];
    return true;
}

/// Whether output e of `field`, evaluated, is zero to round-off: within 1e-9 of the cell h,
/// scaled by its slope.
bool vanishes(const FeatureField& field, int e, double h) {
    const double g = norm(field.gradient(e));
    return std::fabs(field.value(e)) <= 1e-9 * h * (1 + (std::isfinite(g) ? g : 0));
}

/// Newton's method from p onto the common zero of `want` (2 or 3) of `equations` (outputs of
/// `field`), chosen afresh at each step, in order, as the first independent ones: the
/// minimum-norm step s = Jᵀ(JJᵀ)⁻¹F, as `fortu singular` takes onto an edge (for 3, the plain
/// Newton step onto a corner). With `plane_axis` ≥ 0 the point is also held to the plane
/// p[plane_axis] = plane (where an edge crosses a cell's face). True when it converged within
/// `reach` of the start with every equation zero to round-off.
bool solve_feature(FeatureField& field, const std::vector<int>& equations, int want, Vec& p, double h,
                   double reach, int plane_axis = -1, double plane = 0) {
    const Vec start = p;
    Vec before = p;                   // the last point where every chosen equation was finite
    std::vector<int> chosen_before;
    int ends = 0;  // steps past an end: the others take part of their step only, so they get more steps
    for (int iteration = 0; iteration < 40 + ends; ++iteration) {
        field.at(p);
        // A step past where an equation ends (X^0.2 at X = 0, its slope infinite there, so
        // Newton's step from X overshoots to −4X, where it is NaN): its root is that end,
        // found by bisection between the last point it and its gradient were finite at and
        // this one.
        auto ended = [&](bool or_slope) {
            for (int e : chosen_before)
                if (!std::isfinite(field.value(e)) || (or_slope && !finite(field.gradient(e)))) return true;
            return false;
        };
        if (ended(false) && ends < kMaxEnds) {
            ++ends;
            Vec finite_end = before, beyond = p;
            for (int halving = 0; halving < kEndBisections; ++halving) {
                const Vec middle = midpoint(finite_end, beyond);
                if (middle == finite_end || middle == beyond) break;
                p = middle;
                field.at(p);
                (ended(true) ? beyond : finite_end) = middle;
            }
            p = finite_end;
            field.at(p);
        }
        if (norm(sub(p, start)) > reach) return false;
        before = p;
        std::vector<int> chosen;
        if (!choose_independent(field, equations, want, chosen)) return false;
        chosen_before = chosen;
        std::vector<Vec> rows;
        std::vector<double> rhs;
        for (int e : chosen) rows.push_back(field.gradient(e)), rhs.push_back(field.value(e));
        if (plane_axis >= 0) {
            Vec e{0, 0, 0};
            e[plane_axis] = 1;
            rows.push_back(e), rhs.push_back(p[plane_axis] - plane);
        }
        Vec step;
        if (!min_norm_step(rows, rhs, step)) return false;
        for (int k = 0; k < 3; ++k) p[k] -= step[k];
        if (plane_axis >= 0) p[plane_axis] = plane;
        if (!finite(p)) return false;
        if (norm(step) <= kStepTolerance * h) {
            if (norm(sub(p, start)) > reach) return false;
            field.at(p);
            for (int e : equations)
                if (!vanishes(field, e, h)) return false;
            return true;
        }
    }
    return false;
}

struct Cell {
    Vec lo, hi;
    double h;  ///< the longest side
    bool contains(const Vec& p, double margin) const {
        for (int a = 0; a < 3; ++a)
            if (p[a] < lo[a] - margin || p[a] > hi[a] + margin) return false;
        return true;
    }
    /// The face planes (axis·2 + side) p lies on, within `tolerance`, as a bit set.
    int faces_of(const Vec& p, double tolerance) const {
        int bits = 0;
        for (int a = 0; a < 3; ++a) {
            if (std::fabs(p[a] - lo[a]) <= tolerance) bits |= 1 << (2 * a);
            if (std::fabs(p[a] - hi[a]) <= tolerance) bits |= 1 << (2 * a + 1);
        }
        return bits;
    }
};

/// across `direction`, keep their orientation, are not degenerate, and wind once around it:
/// the surface there is then a graph over that plane.
bool star_is_graph(const std::vector<Tri>& star, uint32_t apex, const std::vector<Vec>& at, const Vec& direction,
                   double h) {
    const Vec d = direction;
    const Vec helper = std::fabs(d[0]) < 0.6 ? Vec{1, 0, 0} : Vec{0, 1, 0};
    Vec e1 = cross(d, helper);
    const double l1 = norm(e1);
    for (double& c : e1) c /= l1;
    const Vec e2 = cross(d, e1);
    double turn = 0;
    for (const Tri& t : star) {
        if (t[0] != apex) return false;
        const Vec u = sub(at[t[1]], at[t[0]]), v = sub(at[t[2]], at[t[0]]);
        if (!(norm(cross(u, v)) / 2 >= kMinArea * h * h)) return false;
        const double ux = dot(u, e1), uy = dot(u, e2), vx = dot(v, e1), vy = dot(v, e2);
        const double area = (ux * vy - uy * vx) / 2;
        if (!(area >= kMinProjectedArea * h * h)) return false;
        turn += std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
    }
    return std::fabs(turn - 2 * std::numbers::pi) < 1e-6;
}

/// A direction the star is a graph along, from each of `tries` in turn, moved towards the
/// unit normal of the triangle that faces it least (a perceptron: it finds one when the
/// normals leave a cone, as a corner's three faces do when a face lies on a grid plane).
bool graph_direction(const std::vector<Tri>& star, uint32_t apex, const std::vector<Vec>& at,
                     const std::vector<Vec>& tries, double h, Vec& found) {
    std::vector<Vec> normals;
    for (const Tri& t : star) {
        const Vec n = cross(sub(at[t[1]], at[t[0]]), sub(at[t[2]], at[t[0]]));
        const double length = norm(n);
        if (!(length > 0)) return false;
        normals.push_back({n[0] / length, n[1] / length, n[2] / length});
    }
    for (Vec d : tries)
        for (int step = 0; step < 32; ++step) {
            const double length = norm(d);
            if (!(length > 0)) break;
            for (double& c : d) c /= length;
            if (star_is_graph(star, apex, at, d, h)) {
                found = d;
                return true;
            }
            std::size_t worst = 0;
            for (std::size_t i = 1; i < normals.size(); ++i)
                if (dot(normals[i], d) < dot(normals[worst], d)) worst = i;
            for (int a = 0; a < 3; ++a) d[a] += 0.5 * normals[worst][a];
        }
    return false;
}

/// Whether segments ab and cd of the plane cross at a point that is not an end they share.
bool segments_cross_2d(const std::array<double, 2>& a, const std::array<double, 2>& b, const std::array<double, 2>& c,
                       const std::array<double, 2>& d, double eps) {
    auto side = [&](const std::array<double, 2>& p, const std::array<double, 2>& q, const std::array<double, 2>& r) {
        const double v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        return v > eps ? 1 : v < -eps ? -1 : 0;
    };
    const int s1 = side(a, b, c), s2 = side(a, b, d), s3 = side(c, d, a), s4 = side(c, d, b);
    if (s1 * s2 < 0 && s3 * s4 < 0) return true;
    auto near_segment = [&](const std::array<double, 2>& p, const std::array<double, 2>& q,
                            const std::array<double, 2>& r) {  // r on pq, not at its ends
        const double t = ((r[0] - p[0]) * (q[0] - p[0]) + (r[1] - p[1]) * (q[1] - p[1])) /
                         ((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]));
        return t > 1e-9 && t < 1 - 1e-9;
    };
    // Collinear touching that is not a shared end.
    return (s1 == 0 && near_segment(a, b, c)) || (s2 == 0 && near_segment(a, b, d)) ||
           (s3 == 0 && near_segment(c, d, a)) || (s4 == 0 && near_segment(c, d, b));
}

/// Whether triangle abc meets the inside of the box [lo, hi] (the separating axis test: the
/// box's three axes, the triangle's normal and the nine cross products of their edges).
bool triangle_enters_box(const Vec& a, const Vec& b, const Vec& c, const Vec& lo, const Vec& hi) {
    const Vec centre{(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
    const Vec half{(hi[0] - lo[0]) / 2, (hi[1] - lo[1]) / 2, (hi[2] - lo[2]) / 2};
    const std::array<Vec, 3> v{sub(a, centre), sub(b, centre), sub(c, centre)};
    const std::array<Vec, 3> edges{sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
    auto separates = [&](const Vec& axis) {
        const double p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
        const double r = half[0] * std::fabs(axis[0]) + half[1] * std::fabs(axis[1]) + half[2] * std::fabs(axis[2]);
        return std::min({p0, p1, p2}) >= r || std::max({p0, p1, p2}) <= -r;  // touching is not entering
    };
    for (int k = 0; k < 3; ++k) {
        Vec axis{0, 0, 0};
        axis[k] = 1;
        if (separates(axis)) return false;
        for (const Vec& e : edges)
            if (const Vec x = cross(axis, e); dot(x, x) > 0 && separates(x)) return false;
    }
    const Vec n = cross(edges[0], edges[1]);
    return !(dot(n, n) > 0 && separates(n));
}

/// A point where an R-operation's edge curve crosses a face between two cells: a vertex of
/// the mesh, shared by the two cells' patches. On a grid edge or a grid node (a solid's edge
/// on the lattice) it lies on several faces; it goes into one segment of the cells' patch
/// boundaries, chosen once for all cells, so the two cells of that segment's face take it.
/// Where the curve goes through a node from one cell to one that shares no face with that
/// segment's, a clone (the same vertex) goes into a segment of that cell too.
struct Crossing {
    uint32_t vertex;   ///< its index among the positions
    int operation;
    uint64_t face;     ///< where it goes: the lower cell·3 + the face's axis (set by choose_segments)
    std::pair<uint32_t, uint32_t> segment{UINT32_MAX, UINT32_MAX};  ///< the patch boundary segment it goes into
    bool alive = true;
    /// It is a marching-tetrahedra vertex already (a grid or face diagonal edge through the
    /// curve), moved onto the curve exactly; every cell whose boundary holds it joins there.
    bool on_mesh_vertex = false;
};

/// Points joined into pieces by links (union-find): a wedge's trees, and the test that its
/// links are one piece.
struct Pieces {
    std::map<int, int> parent;
    void add(int x) { parent[x] = x; }
    bool has(int x) const { return parent.count(x) > 0; }
    int root(int x) { return parent[x] == x ? x : parent[x] = root(parent[x]); }
    /// Joins the pieces of x and y; false if they were one already.
    bool join(int x, int y) {
        const int rx = root(x), ry = root(y);
        parent[rx] = ry;
        return rx != ry;
    }
};

/// Features in cells marching tetrahedra left empty: where the solid is thinner than a cell
/// (an acute edge's wedge, a tip whose cell holds no node inside), the traced crossings there
/// have no patch segment to go into. Such crossings (and tips), joined by their links, form a
/// tree whose leaves are crossings on patches (or one loop with branches, the edges round a
/// face); the patches of a block of cells around it are redone together, cut along the tree
/// (wedges_ in ChainBuilder).
struct Wedge {
    std::vector<int> nodes;  ///< crossings with no segment, and tips as -1 - index
    std::vector<uint64_t> seeds;  ///< the cells with triangles that hold a link into the tree
    std::array<std::pair<long, long>, 3> span;  ///< per axis, the cells the tree's points lie in
    int radius = 0;               ///< of the block tried last
    /// Only grid nodes a curve passes diagonally: the cells around them alone (radius 0), as a
    /// wider block would trade their marching-tetrahedra vertices for triangles cells long
    /// (Steinmetz at 13 nodes: a third of the mesh's triangles).
    bool around_nodes = false;
    Cell block;                   ///< the cells within `radius` of the span
    std::vector<uint64_t> cells;  ///< sorted: the cells with triangles joined, of the block
    /// A band instead of trees: the crossings of a closed crease, in order round it, whose
    /// trees are all gaps; its joined patch is an annulus, cut along the crease into two
    /// (build_band).
    std::vector<int> cycle;
    std::vector<uint64_t> tube;  ///< sorted: a band's cells within `radius` of its crease's
    std::vector<uint64_t> left_out;  ///< the cells there holding another edge's crossing or link
};

/// The sharp-feature pass: traces the edge curves cell to cell, puts a vertex where each
/// crosses a cell face and one at each corner, and re-triangulates the cells they cross.
class ChainBuilder {
public:
    ChainBuilder(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh)
        : field_(graph, root), mesh_(mesh) {
        const Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
        for (int a = 0; a < 3; ++a) {
            min_[a] = axes[a]->min;
            step_[a] = axes[a]->step();
            cells_[a] = axes[a]->nodes - 1;
        }
        positions_ = mesh.vertices;
        normals_ = mesh.normals;
    }

    bool has_operations() const { return !field_.operations().empty(); }

    std::array<uint64_t, 3> coords(uint64_t id) const {
        return {id % uint64_t(cells_[0]), id / uint64_t(cells_[0]) % uint64_t(cells_[1]),
                id / (uint64_t(cells_[0]) * uint64_t(cells_[1]))};
    }
    uint64_t stride(int a) const { return a == 0 ? 1 : a == 1 ? uint64_t(cells_[0]) : uint64_t(cells_[0]) * uint64_t(cells_[1]); }
    /// The cell at (x, y, z), as coords() reads it.
    uint64_t cell_id(uint64_t x, uint64_t y, uint64_t z) const { return x + stride(1) * y + stride(2) * z; }

    Cell cell_box(uint64_t id) const {
        const auto c = coords(id);
        Cell cell;
        cell.h = 0;
        for (int a = 0; a < 3; ++a) {
            cell.lo[a] = min_[a] + double(c[a]) * step_[a];
            cell.hi[a] = min_[a] + double(c[a] + 1) * step_[a];
            cell.h = std::max(cell.h, step_[a]);
        }
        return cell;
    }

    /// The box of `cells` together.
    Cell joined_box(const std::vector<uint64_t>& cells) const {
        Cell box = cell_box(cells.front());
        for (uint64_t id : cells) {
            const Cell other = cell_box(id);
            for (int a = 0; a < 3; ++a) box.lo[a] = std::min(box.lo[a], other.lo[a]), box.hi[a] = std::max(box.hi[a], other.hi[a]);
        }
        return box;
    }

    /// Which cells have triangles (a patch): edges lying on the lattice may be joined only in
    /// cells whose neighbours across that face or grid edge have none.
    void set_patch_test(std::function<bool(uint64_t)> has_patch) { has_patch_ = std::move(has_patch); }

    /// The cells refined for thin parts (sorted): their patches are many small pieces of the
    /// fine lattice's marching tetrahedra, not one cell's, so they are left as they are, and no
    /// crossing goes on their faces. The cells joining them are redone like any other: their
    /// patches meet their faces in marching-tetrahedra segments, as the lattice's cells do.
    void set_frozen(const std::vector<uint64_t>& cells, std::vector<char> triangles) {
        frozen_ = cells;
        frozen_triangles_ = std::move(triangles);
    }
    bool frozen(uint64_t id) const { return std::binary_search(frozen_.begin(), frozen_.end(), id); }
    bool any_frozen(const std::vector<uint64_t>& cells) const {
        return std::any_of(cells.begin(), cells.end(), [&](uint64_t id) { return frozen(id); });
    }

    /// The operations that cut the model by its caps' planes (sharpen_features).
    void set_caps(const std::vector<ir::NodeId>& cap_nodes) {
        const auto& ops = field_.operations();
        is_cap_.assign(ops.size(), 0);
        for (std::size_t k = 0; k < ops.size(); ++k)
            is_cap_[k] = std::find(cap_nodes.begin(), cap_nodes.end(), ops[k].node) != cap_nodes.end();
    }

    // ---- The lattice: points on grid planes (features on grid edges and nodes) --------------

    double lattice_h() const { return std::max({step_[0], step_[1], step_[2]}); }

    /// The grid plane index p[a] lies on within 1e-9 of a cell, or -1.
    long plane_of(const Vec& p, int a) const {
        const double k = std::round((p[a] - min_[a]) / step_[a]);
        if (k < 0 || k > cells_[a]) return -1;
        return std::fabs(min_[a] + k * step_[a] - p[a]) <= 1e-9 * lattice_h() ? long(k) : -1;
    }

    /// p with the coordinates that lie on a grid plane to round-off put exactly on it, so a
    /// feature on a grid edge or node is shared exactly by the cells around it.
    Vec snapped(Vec p) const {
        for (int a = 0; a < 3; ++a) {
            const long k = plane_of(p, a);
            if (k >= 0) p[a] = min_[a] + double(k) * step_[a];
        }
        return p;
    }

    /// Per axis, the cell indices whose closed extent holds p[a] (two on an inner grid plane).
    std::array<std::vector<uint64_t>, 3> cell_ranges(const Vec& p) const {
        std::array<std::vector<uint64_t>, 3> r;
        for (int a = 0; a < 3; ++a) {
            const long k = plane_of(p, a);
            if (k >= 0) {
                if (k > 0) r[a].push_back(uint64_t(k - 1));
                if (k < cells_[a]) r[a].push_back(uint64_t(k));
            } else {
                const double f = std::floor((p[a] - min_[a]) / step_[a]);
                if (f >= 0 && f < cells_[a]) r[a].push_back(uint64_t(f));
            }
        }
        return r;
    }

    /// The cells whose closed box holds p: one, or up to eight around a grid node.
    std::vector<uint64_t> cells_around(const Vec& p) const {
        const auto r = cell_ranges(p);
        std::vector<uint64_t> out;
        for (uint64_t z : r[2])
            for (uint64_t y : r[1])
                for (uint64_t x : r[0]) out.push_back(cell_id(x, y, z));
        return out;
    }

    /// The inner faces (lower cell·3 + axis) that hold p: one inside a face, up to twelve at a node.
    std::vector<uint64_t> faces_around(const Vec& p) const {
        const auto r = cell_ranges(p);
        std::vector<uint64_t> out;
        for (int a = 0; a < 3; ++a) {
            if (r[a].size() != 2) continue;
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (uint64_t i : r[b])
                for (uint64_t j : r[c]) out.push_back((r[a][0] * stride(a) + i * stride(b) + j * stride(c)) * 3 + uint64_t(a));
        }
        return out;
    }

    /// Whether a new mesh edge of cell `id` lying on its faces `faces` (bits axis·2 + side)
    /// is free: no other cell that holds that face or grid edge has triangles there.
    bool boundary_edge_free(uint64_t id, int faces) const {
        const auto c = coords(id);
        std::vector<std::array<int, 3>> offsets{{0, 0, 0}};
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side) {
                if (!(faces >> (2 * a + side) & 1)) continue;
                const std::size_t n = offsets.size();
                for (std::size_t i = 0; i < n; ++i) {
                    auto o = offsets[i];
                    o[a] = side ? 1 : -1;
                    offsets.push_back(o);
                }
            }
        for (const auto& o : offsets) {
            if (o == std::array<int, 3>{0, 0, 0}) continue;
            uint64_t other = 0;
            bool inside = true;
            for (int a = 0; a < 3; ++a) {
                const long k = long(c[a]) + o[a];
                if (k < 0 || k >= cells_[a]) inside = false;
                else other += uint64_t(k) * stride(a);
            }
            if (inside && has_patch_ && has_patch_(other)) return false;
        }
        return true;
    }

    /// Whether cell `id` holds a crossing or link of `crease` (first) and one of another edge
    /// (second); a link with one end on each counts for both.
    std::pair<bool, bool> crease_holdings(uint64_t id, const std::set<int>& crease) const {
        bool own = false, other = false;
        for (int x : crossings_in(id)) (crease.count(x) ? own : other) = true;
        if (const auto it = links_.find(id); it != links_.end())
            for (const auto& [a, b] : it->second) {
                own |= crease.count(a) || crease.count(b);
                other |= !crease.count(a) || !crease.count(b);
            }
        return {own, other};
    }

    /// Whether every cell with triangles whose closed box holds p is one of `joined` (sorted).
    bool patches_around_joined(const Vec& p, const std::vector<uint64_t>& joined) const {
        for (uint64_t id : cells_around(p))
            if (!std::binary_search(joined.begin(), joined.end(), id) && (!has_patch_ || has_patch_(id))) return false;
        return true;
    }

    /// The cells whose closed box holds both p and q.
    std::vector<uint64_t> cells_holding(const Vec& p, const Vec& q) const {
        const std::vector<uint64_t> other = cells_around(q);
        std::vector<uint64_t> out;
        for (uint64_t cell : cells_around(p))
            if (std::find(other.begin(), other.end(), cell) != other.end()) out.push_back(cell);
        return out;
    }

    /// Whether a group's new edge from p to q touches no cell outside the group that has
    /// triangles (every cell whose closed box holds both ends).
    bool chord_free(const std::vector<uint64_t>& group, const Vec& p, const Vec& q) const {
        for (uint64_t cell : cells_holding(p, q))
            if (std::find(group.begin(), group.end(), cell) == group.end() && has_patch_ && has_patch_(cell)) return false;
        return true;
    }

    /// Phase 1, per cell with triangles: a cell whose normals disagree seeds the traces of the
    /// edge curves through it, and may hold a corner.
    void seed(uint64_t id, const std::vector<uint32_t>& patch, FeatureStats& stats) {
        if (frozen(id) || !normals_disagree(patch)) return;
        ++stats.cells_tested;
        const Cell cell = cell_box(id);
        const std::vector<int> candidates = vanishing_operations(cell);
        if (candidates.empty()) return;
        if (candidates.size() >= 2) corner_cells_.push_back(id);
        Vec seed{0, 0, 0};
        std::size_t count = 0;
        for (uint32_t t : patch)
            for (uint32_t v : mesh_.triangles[t]) {
                for (int a = 0; a < 3; ++a) seed[a] += mesh_.vertices[v][a];
                ++count;
            }
        for (double& c : seed) c /= double(count);
        const auto& ops = field_.operations();
        for (int k : candidates) {
            if (visited_.count(visit_key(id, k))) continue;
            // The nearest point of the edge to the patch may lie outside the cell where the
            // edge only clips it: then from that point pulled back into the cell, again.
            Vec p = seed;
            bool inside = false, converged = false;
            for (int round = 0; round < 4 && !inside; ++round) {
                if (round > 0)
                    for (int a = 0; a < 3; ++a) p[a] = std::clamp(p[a], cell.lo[a], cell.hi[a]);
                converged = solve_feature(field_, {ops[k].a, ops[k].b}, 2, p, cell.h, 2 * cell.h);
                if (!converged) break;
                inside = cell.contains(p, 0);
            }
            p = snapped(p);
            uint64_t start = id;
            if (!inside && !(converged && empty_cell_beside(id, p, start))) continue;
            if (start != id && visited_.count(visit_key(start, k))) continue;
            if (!on_boundary(p, k, cell.h)) continue;
            const int plus = walk(k, start, p, 1), minus = walk(k, start, p, -1);
            if (plus >= 0 && minus >= 0 && plus != minus) add_link(plus, minus);
        }
    }

    /// Whether the edge point p found from cell `id` lies in a cell next to it (sharing a face,
    /// an edge or a node) that has no triangles, set as `cell`: an acute edge's wedge thinner
    /// than a cell leaves every cell along the edge empty (the 39° edge of the FLOZ3 plate at
    /// 37 nodes), so the edge is traced from the patches beside it or not at all.
    bool empty_cell_beside(uint64_t id, const Vec& p, uint64_t& cell) const {
        for (uint64_t other : cells_around(p)) {
            if ((has_patch_ && has_patch_(other)) || !touching(id, other)) continue;
            cell = other;
            return true;
        }
        return false;
    }

    /// The cells across cell id's faces, in axis order, the lower side first.
    std::vector<uint64_t> face_neighbours(uint64_t id) const {
        std::vector<uint64_t> out;
        const auto c = coords(id);
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side)
                if (side == 0 ? c[a] > 0 : c[a] + 1 < uint64_t(cells_[a])) out.push_back(side ? id + stride(a) : id - stride(a));
        return out;
    }

    /// Whether cells a and b are the same or share a face, an edge or a node.
    bool touching(uint64_t a, uint64_t b) const {
        const auto c = coords(a), o = coords(b);
        for (int k = 0; k < 3; ++k)
            if ((o[k] > c[k] ? o[k] - c[k] : c[k] - o[k]) > 1) return false;
        return true;
    }

    /// Phase 2: corners, then each cell's patch re-triangulated through its feature vertices;
    /// a cell that fails gives up its crossings and its neighbours are redone without them.
    void build(const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of) {
        for (uint64_t id : corner_cells_) find_corner(id);
        for (uint64_t id : end_cells_) find_corner(id);
        cut_chains_at_corners();
        choose_segments(patch_of);
        corners_into_trees();
        plan_wedges(patch_of);
        restore_unplanned_corners();
        plan_edge_groups(patch_of);
        plan_sheet_groups(patch_of);
        std::vector<uint64_t> queue;
        for (const auto& [id, apex] : apex_) queue.push_back(id);
        for (const auto& [id, cells] : groups_) queue.push_back(id);
        for (const auto& [id, wedge] : wedge_of_) queue.push_back(id);
        for (const Crossing& c : crossings_)
            if (c.alive)
                for (uint64_t id : cells_sharing(c)) queue.push_back(id);
        std::sort(queue.begin(), queue.end());
        queue.erase(std::unique(queue.begin(), queue.end()), queue.end());
        std::set<uint64_t> pending(queue.begin(), queue.end());
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1)  // the gaps in the middle of edges, once the tips have their cells
                for (Wedge& wedge : mid_edge_wedges_) {
                    wedges_.push_back(std::move(wedge));
                    if (group_wedge(wedges_.size() - 1))
                        for (uint64_t g : wedges_.back().cells) pending.insert(g);
                }
            while (!pending.empty()) {
                const uint64_t id = *pending.begin();
                pending.erase(pending.begin());
                if (banded_.count(id)) continue;  // redone with its band (plan_wedges)
                std::vector<Tri> triangles;
                if (const auto wedge = wedge_of_.find(id); wedge != wedge_of_.end()) {
                    // Features in cells with no triangles: the patches around them redone together.
                    const std::size_t index = wedge->second;
                    const std::vector<uint64_t> cells = wedges_[index].cells;
                    std::vector<uint32_t> joined;
                    for (uint64_t g : cells) {
                        const auto patch = patch_of(g);
                        if (patch) joined.insert(joined.end(), patch->begin(), patch->end());
                        results_.erase(g);
                        pending.erase(g);
                    }
                    bool disc = false;
                    if (!any_frozen(cells) && build_wedge(wedges_[index], joined, triangles, disc)) {
                        results_[cells.front()] = {std::move(joined), std::move(triangles)};
                        continue;
                    }
                    for (uint64_t g : cells) wedge_of_.erase(g), pending.insert(g);  // each on its own
                    if (!disc && take_in_corners(index))  // a ring round corners' cells: the same block with them
                        --wedges_[index].radius;
                    if (group_wedge(index))  // or a larger block
                        for (uint64_t g : wedges_[index].cells) pending.insert(g);
                    else
                        for (uint64_t g : restore_corners(wedges_[index])) pending.insert(g);
                    continue;
                }
                if (const auto group = groups_.find(id); group != groups_.end()) {
                    // A corner the cells around it share: one fan over their joined patches.
                    const std::vector<uint64_t> cells = group->second;
                    std::vector<uint32_t> joined;
                    bool all = true;
                    for (uint64_t g : cells) {
                        const auto patch = patch_of(g);
                        if (!patch) all = false;
                        else joined.insert(joined.end(), patch->begin(), patch->end());
                    }
                    for (uint64_t g : cells) results_.erase(g), pending.erase(g);  // built once for all
                    if (all && !any_frozen(cells) && build_cell(cells.front(), &joined, triangles, &cells)) {
                        // No triangles: nothing left to join (its crossings died with a
                        // neighbour), so the cells keep marching tetrahedra's patches.
                        if (!triangles.empty()) results_[cells.front()] = {std::move(joined), std::move(triangles)};
                        continue;
                    }
                    for (uint64_t g : cells) {  // each on its own, without the corner
                        groups_.erase(g);
                        apex_.erase(g);
                        pending.insert(g);
                    }
                    continue;
                }
                const std::optional<std::vector<uint32_t>> patch = patch_of(id);
                if (!frozen(id) && build_cell(id, patch ? &*patch : nullptr, triangles)) {
                    if (patch && !triangles.empty()) results_[id] = {*patch, std::move(triangles)};
                    else results_.erase(id);
                    continue;
                }
                results_.erase(id);
                if (frozen(id)) apex_.erase(id);
                else if (apex_.erase(id)) {  // without its corner, the edges may still pass
                    pending.insert(id);
                    continue;
                }
                if (!frozen(id) && add_edge_apex(id)) {  // a fan from a point of the edge keeps the crossings
                    pending.insert(id);
                    continue;
                }
                for (int c : crossings_in(id)) {
                    crossings_[c].alive = false;
                    for (uint64_t other : cells_sharing(crossings_[c]))
                        if (other != id) pending.insert(other);
                }
            }
        }
    }

    /// The mesh with the re-triangulated patches, the chamfers left lifted onto their edges
    /// (lift_chamfers) and unused vertices dropped; with `stats`, the feature vertices and
    /// chain edges counted on it (the crossings left off are counted on the finished mesh, by
    /// the cover pass: CoverStats); for a query, its cells found (find_cells_to_refine,
    /// `patch_of` as for build()).
    /// With a `query` that finds cells to refine (RefineQuery), the mesh is left as it was (false).
    /// `left`: the crossings that are not vertices of the finished mesh.
    bool finish(const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of, FeatureStats* stats,
                RefineQuery* query, std::vector<std::array<double, 3>>* left) {
        std::vector<char> removed(mesh_.triangles.size(), 0);
        std::vector<Tri> triangles;
        std::vector<uint32_t> kept;  // the marching-tetrahedra triangles kept, as they were numbered
        for (const auto& [id, result] : results_)
            for (uint32_t t : result.first) removed[t] = 1;
        for (uint32_t t = 0; t < mesh_.triangles.size(); ++t)
            if (!removed[t]) triangles.push_back(mesh_.triangles[t]), kept.push_back(t);
        for (const auto& [id, result] : results_) triangles.insert(triangles.end(), result.second.begin(), result.second.end());
        std::vector<char> fixed(triangles.size(), 0);  // a frozen cell's: no chamfer takes them
        if (!frozen_triangles_.empty())
            for (std::size_t t = 0; t < kept.size(); ++t) fixed[t] = frozen_triangles_[kept[t]];
        const std::vector<char> gone = lift_chamfers(triangles, fixed);
        std::vector<Tri> remaining;
        remaining.reserve(triangles.size());
        for (std::size_t t = 0; t < kept.size(); ++t)
            if (gone[t]) removed[kept[t]] = 1;
            else remaining.push_back(triangles[t]);
        const std::size_t first_redone = remaining.size();
        for (std::size_t t = kept.size(); t < triangles.size(); ++t)
            if (!gone[t]) remaining.push_back(triangles[t]);
        triangles = std::move(remaining);
        if (query) {
            find_cells_to_refine(triangles, first_redone, removed, patch_of, *query);
            if (!query->refine.empty()) return false;
        }
        std::vector<char> used(positions_.size(), 0);
        if (stats || left)
            for (const Tri& t : triangles)
                for (uint32_t v : t) used[v] = 1;
        if (stats) {
            for (const Crossing& c : crossings_) stats->edge_vertices += used[c.vertex];
            std::set<uint32_t> corners;
            for (const auto& [id, apex] : apex_)
                if (used[apex]) corners.insert(apex);
            for (uint32_t tip : tips_)
                if (used[tip]) corners.insert(tip);
            stats->corner_vertices = corners.size();
            stats->chain_edges = chain_edges_;
        }
        if (left)
            for (const Crossing& c : crossings_)
                if (!used[c.vertex]) left->push_back(positions_[c.vertex]);
        Mesh out{positions_, normals_, std::move(triangles)};
        drop_unused_vertices(out);
        mesh_ = std::move(out);
        return true;
    }

private:
    // ---- Chamfers lifted onto their edges: the last pass, on the finished mesh ----------------

    /// Which of operation k's faces vertex v lies on (first order, within kChamferTolerance
    /// cells): 1 operand a's only, 2 b's only, 3 both (the edge), 0 neither.
    int face_side(uint32_t v, int k, double h) const {
        field_.at(positions_[v]);
        const auto& op = field_.operations()[k];
        auto on = [&](int i) {
            const double slope = norm(field_.gradient(i));
            return std::isfinite(slope) && std::fabs(field_.value(i)) <= kChamferTolerance * h * slope;
        };
        return (on(op.a) ? 1 : 0) | (on(op.b) ? 2 : 0);
    }

    /// Runs of traced crossings off the mesh (`used`: the vertices it has) between two on it,
    /// each as its vertices from one of those to the other along the edge's links.
    std::vector<std::pair<int, std::vector<uint32_t>>> runs_off_mesh(const std::vector<char>& used) const {
        std::vector<std::pair<int, std::vector<uint32_t>>> runs;
        std::set<std::pair<uint32_t, uint32_t>> started;  // a run's first two vertices, from either end
        for (int x = 0; x < int(crossings_.size()); ++x) {
            const auto it = partners_.find(x);
            if (!used[crossings_[x].vertex] || it == partners_.end()) continue;
            for (int y : it->second) {
                if (used[crossings_[y].vertex] || crossings_[y].operation != crossings_[x].operation) continue;
                std::vector<uint32_t> run{crossings_[x].vertex, crossings_[y].vertex};
                bool ended = false;
                for (int previous = x, at = y; run.size() <= kMaxChamferRun;) {
                    const auto next = partners_.find(at);
                    if (next == partners_.end() || next->second.size() != 2) break;  // a branch or an end
                    const int ahead = next->second[0] == previous ? next->second[1] : next->second[0];
                    if (crossings_[ahead].operation != crossings_[x].operation) break;
                    previous = at, at = ahead;
                    run.push_back(crossings_[at].vertex);
                    if (used[crossings_[at].vertex]) {
                        ended = true;
                        break;
                    }
                }
                if (!ended || run.front() == run.back() || started.count({run[0], run[1]})) continue;
                started.insert({run[0], run[1]});
                started.insert({run.back(), run[run.size() - 2]});
                runs.push_back({crossings_[x].operation, std::move(run)});
            }
        }
        return runs;
    }

    /// Where a traced edge's crossings are off the finished mesh (`triangles`) between two
    /// crossings on it (a wedge thinner than a cell whose cells or block failed: Tor1's twisted
    /// edges at every size), marching tetrahedra cut across the wedge: a chamfer, triangles
    /// each with vertices on both operands' faces. Found by the faces its vertices lie on, not
    /// by distance, it is a disc from one crossing on the mesh to the next, one side on each
    /// face; it is replaced by two strips of least area from its sides to the crossings
    /// between (loft_open), if they face the way the surface does, stay near it and cross
    /// neither each other nor the triangles around. The strips go on the end of `triangles`;
    /// returns which of them are gone.
    std::vector<char> lift_chamfers(std::vector<Tri>& triangles, const std::vector<char>& fixed) {
        std::vector<char> gone(triangles.size(), 0);
        const double h = lattice_h();
        std::vector<char> used(positions_.size(), 0);
        for (const Tri& t : triangles)
            for (uint32_t v : t) used[v] = 1;
        const auto runs = runs_off_mesh(used);
        if (runs.empty()) return gone;
        // Only triangles whose boxes meet the runs' box, widened by the buckets kept round
        // them, matter (a model's runs are usually a few places on a large mesh).
        const double bucket = kChamferReach * h;
        Vec lo = positions_[runs[0].second[0]], hi = lo;
        for (const auto& [k, run] : runs)
            for (uint32_t v : run)
                for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], positions_[v][a]), hi[a] = std::max(hi[a], positions_[v][a]);
        for (int a = 0; a < 3; ++a) lo[a] -= 3 * bucket, hi[a] += 3 * bucket;
        std::vector<uint32_t> relevant;
        for (uint32_t t = 0; t < triangles.size(); ++t) {
            bool apart = false;
            for (int a = 0; a < 3 && !apart; ++a) {
                const double p = positions_[triangles[t][0]][a], q = positions_[triangles[t][1]][a], r = positions_[triangles[t][2]][a];
                apart = std::max({p, q, r}) < lo[a] || std::min({p, q, r}) > hi[a];
            }
            if (!apart) relevant.push_back(t);
        }
        // Their vertices' triangles (CSR), and the triangles in buckets three cells wide near
        // the runs, each in every bucket its bounding box meets (so a strip's box finds every
        // triangle that could cross it).
        std::vector<uint32_t> first(positions_.size() + 1, 0), incident(relevant.size() * 3);
        for (uint32_t t : relevant)
            for (uint32_t v : triangles[t]) ++first[v + 1];
        for (std::size_t v = 0; v < positions_.size(); ++v) first[v + 1] += first[v];
        {
            std::vector<uint32_t> fill(first.begin(), first.end() - 1);
            for (uint32_t t : relevant)
                for (uint32_t v : triangles[t]) incident[fill[v]++] = t;
        }
        auto bucket_of = [&](double c) { return long(std::floor(c / bucket)); };
        auto key = [](long x, long y, long z) { return (uint64_t(x) & 0x1fffff) | (uint64_t(y) & 0x1fffff) << 21 | (uint64_t(z) & 0x1fffff) << 42; };
        std::unordered_map<uint64_t, std::vector<uint32_t>> near;
        for (const auto& [k, run] : runs)
            for (uint32_t v : run) {
                const Vec& p = positions_[v];
                for (long dz = -2; dz <= 2; ++dz)
                    for (long dy = -2; dy <= 2; ++dy)
                        for (long dx = -2; dx <= 2; ++dx) near.try_emplace(key(bucket_of(p[0]) + dx, bucket_of(p[1]) + dy, bucket_of(p[2]) + dz));
            }
        // Calls visit(bucket) for each bucket the box of `points` meets; false if one is not kept.
        auto buckets_meeting = [&](const std::vector<const Vec*>& points, const auto& visit) {
            long lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
                double l = (*points[0])[a], u = l;
                for (const Vec* p : points) l = std::min(l, (*p)[a]), u = std::max(u, (*p)[a]);
                lo[a] = bucket_of(l), hi[a] = bucket_of(u);
            }
            bool all = true;
            for (long z = lo[2]; z <= hi[2]; ++z)
                for (long y = lo[1]; y <= hi[1]; ++y)
                    for (long x = lo[0]; x <= hi[0]; ++x)
                        if (const auto it = near.find(key(x, y, z)); it != near.end()) visit(it->second);
                        else all = false;
            return all;
        };
        auto file = [&](uint32_t t) {
            buckets_meeting({&positions_[triangles[t][0]], &positions_[triangles[t][1]], &positions_[triangles[t][2]]},
                            [&](std::vector<uint32_t>& in) { in.push_back(t); });
        };
        for (uint32_t t : relevant) file(t);
        // Corners (where three operands vanish) and crossings: a chamfer may drop neither.
        std::vector<uint32_t> kept(tips_.begin(), tips_.end());
        for (const auto& [id, apex] : apex_)
            if (apex_equations_.at(id).size() >= 3) kept.push_back(apex);
        for (const Crossing& c : crossings_) kept.push_back(c.vertex);
        std::sort(kept.begin(), kept.end());
        // One run's chamfer replaced (lift_chamfer), if its strips cross no triangle around them.
        auto lift = [&](int k, const std::vector<uint32_t>& run, int& leak) {
            std::vector<Tri> strips;
            std::vector<uint32_t> region;
            if (!lift_chamfer(run, k, h, triangles, gone, first, incident, kept, region, strips, leak)) return false;
            if (std::any_of(region.begin(), region.end(), [&](uint32_t t) { return t < fixed.size() && fixed[t]; })) return false;
            // Nor may the strips cross the triangles around them (earlier strips included),
            // each looked for in the buckets its box meets.
            std::sort(region.begin(), region.end());
            for (const Tri& t : strips) {
                std::vector<Tri> around;
                if (!buckets_meeting({&positions_[t[0]], &positions_[t[1]], &positions_[t[2]]}, [&](const std::vector<uint32_t>& in) {
                        for (uint32_t s : in)
                            if (!gone[s] && !std::binary_search(region.begin(), region.end(), s)) around.push_back(triangles[s]);
                    }))
                    return false;
                if (triangles_cross({t}, around, h)) return false;
            }
            // An edge between two vertices of the mesh (a fan from a run's end over a side) must
            // not be one it has outside the chamfer.
            std::set<std::pair<uint32_t, uint32_t>> chamfer_edges;
            for (uint32_t t : region)
                for (int e = 0; e < 3; ++e) chamfer_edges.insert(std::minmax(triangles[t][e], triangles[t][(e + 1) % 3]));
            for (const Tri& t : strips)
                for (int e = 0; e < 3; ++e) {
                    const uint32_t u = t[e], w = t[(e + 1) % 3];
                    if (!used[u] || !used[w] || chamfer_edges.count(std::minmax(u, w))) continue;
                    for (uint32_t i = first[u]; i < first[u + 1]; ++i) {
                        const Tri& o = triangles[incident[i]];
                        if (!gone[incident[i]] && !std::binary_search(region.begin(), region.end(), incident[i]) &&
                            std::find(o.begin(), o.end(), w) != o.end())
                            return false;
                    }
                }
            for (uint32_t t : region) gone[t] = 1;
            for (const Tri& t : strips) {
                triangles.push_back(t);
                gone.push_back(0);
                file(uint32_t(triangles.size() - 1));
            }
            chain_edges_ += run.size() - 1;
            return true;
        };
        // A chamfer that goes on past a run's end (beneath its crossing, a tent's top) is
        // lifted with the run beyond that end too, through the crossing.
        std::map<std::pair<int, uint32_t>, std::vector<std::size_t>> runs_at;  // (operation, end) → runs
        for (std::size_t i = 0; i < runs.size(); ++i)
            for (uint32_t end : {runs[i].second.front(), runs[i].second.back()}) runs_at[{runs[i].first, end}].push_back(i);
        std::vector<char> lifted(runs.size(), 0);
        for (std::size_t i = 0; i < runs.size(); ++i) {
            const int k = runs[i].first;
            std::vector<uint32_t> run = runs[i].second;
            std::vector<std::size_t> joined{i};
            for (int joins = 0; !lifted[i] && joins <= kMaxChamferJoins; ++joins) {
                int leak = 0;
                if (lift(k, run, leak)) {
                    for (std::size_t j : joined) lifted[j] = 1;
                    break;
                }
                if (leak == 0) break;
                const std::vector<std::size_t>& meeting = runs_at[{k, leak == 1 ? run.front() : run.back()}];
                if (meeting.size() != 2) break;
                const std::size_t j = std::count(joined.begin(), joined.end(), meeting[0]) ? meeting[1] : meeting[0];
                if (lifted[j] || std::count(joined.begin(), joined.end(), j)) break;
                std::vector<uint32_t> beyond = runs[j].second;
                if (leak == 1) {
                    if (beyond.back() != run.front()) std::reverse(beyond.begin(), beyond.end());
                    run.insert(run.begin(), beyond.begin(), beyond.end() - 1);
                } else {
                    if (beyond.front() != run.back()) std::reverse(beyond.begin(), beyond.end());
                    run.insert(run.end(), beyond.begin() + 1, beyond.end());
                }
                if (run.front() == run.back()) break;  // round a closed edge
                joined.push_back(j);
            }
        }
        return gone;
    }

    /// One run's chamfer (lift_chamfers): the triangles reached across edges from those at the
    /// run's first end, each with a vertex on each of operation k's faces and any others on
    /// the edge at the run's ends (its end crossing, or a point of the edge beside it that a
    /// cell's fan or marching tetrahedra put there), within kChamferReach cells of the run;
    /// a disc whose boundary goes from one end along one face to the other end and back along
    /// the other face. `strips`: its replacement, checked for itself (not yet against the
    /// triangles around). `leak`: 1 or 2 where the chamfer goes on past the run's first or last
    /// end, for lift_chamfers to join the run beyond; `kept` (sorted) may not be dropped.
    bool lift_chamfer(const std::vector<uint32_t>& run, int k, double h, const std::vector<Tri>& triangles,
                      const std::vector<char>& gone, const std::vector<uint32_t>& first, const std::vector<uint32_t>& incident,
                      const std::vector<uint32_t>& kept, std::vector<uint32_t>& region, std::vector<Tri>& strips,
                      int& leak) const {
        leak = 0;
        std::unordered_map<uint32_t, int> sides;
        auto side_of = [&](uint32_t v) {
            const auto [it, fresh] = sides.try_emplace(v, 0);
            if (fresh) it->second = face_side(v, k, h);
            return it->second;
        };
        // Each end: its crossing and the points of the edge the mesh joins to it, one after
        // another, each nearer the run's next crossing (a cell's fan from a point of the edge,
        // a marching-tetrahedra vertex on it).
        auto end_points = [&](uint32_t end, uint32_t inward) {
            std::vector<uint32_t> out{end};
            for (std::size_t at = 0; at < out.size(); ++at) {
                const uint32_t from = out[at];
                const double reach = norm(sub(positions_[inward], positions_[from]));
                for (uint32_t i = first[from]; i < first[from + 1]; ++i)
                    for (uint32_t v : triangles[incident[i]])
                        if (v != from && v != inward && !gone[incident[i]] && side_of(v) == 3 &&
                            norm(sub(positions_[inward], positions_[v])) < reach && std::find(out.begin(), out.end(), v) == out.end())
                            out.push_back(v);
            }
            return out;
        };
        const std::vector<uint32_t> ends[2] = {end_points(run.front(), run[1]), end_points(run.back(), run[run.size() - 2])};
        auto at_end = [&](uint32_t v) {
            for (int e = 0; e < 2; ++e)
                if (std::find(ends[e].begin(), ends[e].end(), v) != ends[e].end()) return e;
            return -1;
        };
        auto near_run = [&](const Vec& c) {
            for (std::size_t i = 0; i + 1 < run.size(); ++i)
                if (segment_distance(c, positions_[run[i]], positions_[run[i + 1]]) <= kChamferReach * h) return true;
            return false;
        };
        // Crossings inside the run that the mesh has (runs joined through them, lift_chamfers):
        // the chamfer passes beneath such a crossing, which a cell's fan lifted as a tent
        // (Tor1), so the whole fan round it goes with the chamfer.
        std::vector<uint32_t> inside;
        for (std::size_t i = 1; i + 1 < run.size(); ++i)
            if (first[run[i] + 1] > first[run[i]]) inside.push_back(run[i]);
        // And the tents' other points on the edge (a cell's fan from one, a marching-tetrahedra
        // vertex on it), not corners or other crossings: the strips drop them.
        for (std::size_t at = 0; at < inside.size() && inside.size() <= 4 * run.size(); ++at)
            for (uint32_t i = first[inside[at]]; i < first[inside[at] + 1]; ++i)
                for (uint32_t v : triangles[incident[i]])
                    if (!gone[incident[i]] && side_of(v) == 3 && at_end(v) < 0 && !std::binary_search(kept.begin(), kept.end(), v) &&
                        std::find(inside.begin(), inside.end(), v) == inside.end())
                        inside.push_back(v);
        auto allowed = [&](uint32_t v) {
            const int side = side_of(v);
            return side == 1 || side == 2 || (side == 3 && (at_end(v) >= 0 || std::find(inside.begin(), inside.end(), v) != inside.end()));
        };
        auto chamfer = [&](uint32_t t) {
            int faces = 0;
            for (uint32_t v : triangles[t]) {
                if (!allowed(v)) return false;
                if (side_of(v) != 3) faces |= side_of(v);
            }
            return faces == 3;
        };
        std::vector<uint32_t> queue;
        std::set<uint32_t> in;
        for (uint32_t v : inside)
            for (uint32_t i = first[v]; i < first[v + 1]; ++i) {
                const uint32_t t = incident[i];
                if (gone[t]) continue;
                for (uint32_t w : triangles[t])
                    if (!allowed(w)) return false;
                if (in.insert(t).second) queue.push_back(t);
            }
        for (uint32_t end : ends[0])
            for (uint32_t i = first[end]; i < first[end + 1]; ++i)
                if (const uint32_t t = incident[i]; !gone[t] && chamfer(t) && in.insert(t).second) queue.push_back(t);
        for (std::size_t at = 0; at < queue.size(); ++at) {
            const Tri& t = triangles[queue[at]];
            if (queue.size() > kMaxChamferTriangles * run.size()) return false;  // not one chamfer's
            if (const Vec c = centroid(t); !near_run(c)) {  // it goes on past an end, or it is not one chamfer's
                const Vec along = sub(positions_[run.back()], positions_[run.front()]);
                const double where = dot(sub(c, positions_[run.front()]), along) / dot(along, along);
                leak = where < 0 ? 1 : where > 1 ? 2 : 0;
                return false;
            }
            for (int e = 0; e < 3; ++e) {
                const uint32_t u = t[e], w = t[(e + 1) % 3];
                for (uint32_t i = first[u]; i < first[u + 1]; ++i) {
                    const uint32_t s = incident[i];
                    const Tri& o = triangles[s];
                    if (gone[s] || in.count(s) || std::find(o.begin(), o.end(), w) == o.end() || !chamfer(s)) continue;
                    in.insert(s);
                    queue.push_back(s);
                }
            }
        }
        region = queue;
        if (region.empty()) return false;
        // The triangles at the run's first end may hold another chamfer meeting this one only
        // there (the run's beyond that end, Chainik and Tor1): of the pieces across edges, the
        // one that reaches the other end is this run's.
        if (!keep_piece_reaching(region, triangles, [&](uint32_t v) { return at_end(v) == 1; },
                                 [&](uint32_t v) { return std::find(inside.begin(), inside.end(), v) != inside.end(); }))
            return false;
        // Its boundary: one loop, the region a disc.
        std::vector<Tri> chamfer_triangles;
        for (uint32_t t : region) chamfer_triangles.push_back(triangles[t]);
        std::vector<std::vector<uint32_t>> rings;
        long euler = 0;
        if (!boundary_rings(chamfer_triangles, nullptr, rings, euler) || rings.size() != 1 || euler != 1) return false;
        std::vector<uint32_t>& loop = rings.front();
        // One point of the edge at each end, and between them one side on each face.
        std::size_t corner[2] = {loop.size(), loop.size()};
        for (std::size_t i = 0; i < loop.size(); ++i) {
            if (side_of(loop[i]) != 3) continue;
            const int e = at_end(loop[i]);
            if (e < 0 || corner[e] != loop.size()) return false;
            corner[e] = i;
        }
        if (corner[0] == loop.size() || corner[1] == loop.size()) {  // it passes an end
            leak = corner[0] == loop.size() ? 1 : 2;
            return false;
        }
        std::rotate(loop.begin(), loop.begin() + long(corner[0]), loop.end());
        const std::size_t other = (corner[1] + loop.size() - corner[0]) % loop.size();
        std::vector<uint32_t> sides_of_loop[2] = {{loop.begin(), loop.begin() + long(other) + 1}, {loop.begin() + long(other), loop.end()}};
        sides_of_loop[1].push_back(loop.front());
        int faces = 0;
        for (const auto& side : sides_of_loop) {
            if (side.size() < 3) return false;
            const int face = side_of(side[1]);
            for (std::size_t i = 1; i + 1 < side.size(); ++i)
                if (side_of(side[i]) != face) return false;
            faces |= face;
        }
        if (faces != 3) return false;
        std::vector<uint32_t> crease{loop.front()};
        crease.insert(crease.end(), run.begin() + 1, run.end() - 1);
        crease.push_back(loop[other]);
        const double reach = kChamferReach * h;
        for (const auto& side : sides_of_loop) {
            if (side.front() != crease.front()) std::reverse(crease.begin(), crease.end());
            if (!loft_open(side, crease, h, reach, strips)) return false;
        }
        return !triangles_cross(strips, strips, h);  // the two strips, and each in itself
    }

    /// `region` (triangles' indices) cut to its one piece across edges with a vertex that
    /// `reaches`; unchanged where it is one piece, or where no piece or several do. False
    /// where a piece left out has a vertex that `must_stay` (a crossing whose fan is lifted).
    static bool keep_piece_reaching(std::vector<uint32_t>& region, const std::vector<Tri>& triangles,
                                    const std::function<bool(uint32_t)>& reaches, const std::function<bool(uint32_t)>& must_stay) {
        Pieces joined;
        std::map<std::pair<uint32_t, uint32_t>, int> with_edge;
        for (int i = 0; i < int(region.size()); ++i) {
            joined.add(i);
            for (int e = 0; e < 3; ++e) {
                const Tri& t = triangles[region[std::size_t(i)]];
                const auto [it, fresh] = with_edge.try_emplace(std::minmax(t[e], t[(e + 1) % 3]), i);
                if (!fresh) joined.join(i, it->second);
            }
        }
        std::set<int> pieces, reaching;
        for (int i = 0; i < int(region.size()); ++i) {
            pieces.insert(joined.root(i));
            for (uint32_t v : triangles[region[std::size_t(i)]])
                if (reaches(v)) reaching.insert(joined.root(i));
        }
        if (pieces.size() == 1 || reaching.size() != 1) return true;
        std::vector<uint32_t> piece;
        for (int i = 0; i < int(region.size()); ++i) {
            if (joined.root(i) == *reaching.begin()) piece.push_back(region[std::size_t(i)]);
            else
                for (uint32_t v : triangles[region[std::size_t(i)]])
                    if (must_stay(v)) return false;
        }
        region = std::move(piece);
        return true;
    }

    /// The strip between two paths from one point to another (`side`, then `crease`, the strip
    /// on the left of `side` going forward): each triangle two points of one and one of the
    /// other, the least total area (dynamic programming, as loft's for closed ones), none
    /// refused by strip_area, no two neighbours folded onto each other.
    bool loft_open(const std::vector<uint32_t>& side, const std::vector<uint32_t>& crease, double h, double reach,
                   std::vector<Tri>& out) const {
        const std::size_t m = side.size() - 1, n = crease.size() - 1;  // the last indices
        if (m < 1 || n < 1 || (m + 1) * (n + 1) > kMaxLoftSize) return false;
        const double inf = std::numeric_limits<double>::infinity();
        const std::size_t width = n + 1;
        std::vector<double> cost((m + 1) * width, inf);
        std::vector<char> along_side((m + 1) * width, 0);  // the last step: 1 along the side, 0 along the crease
        std::unordered_map<uint64_t, bool> midpoints;
        // Rung (i, j) joins side[i] and crease[j]; (1, 0) and (0, 1) are the paths' first edges,
        // (m, n − 1) and (m − 1, n) their last.
        cost[1 * width + 0] = cost[0 * width + 1] = 0;
        for (std::size_t i = 0; i <= m; ++i)
            for (std::size_t j = 0; j <= n; ++j) {
                if (i + j <= 1) continue;
                double& c = cost[i * width + j];
                // A fan from an end over the side would join it to side points the mesh may
                // have joined it to outside the chamfer.
                if (i > 0 && (j > 0 || i == 1) && j < n && cost[(i - 1) * width + j] < inf) {
                    const double next = cost[(i - 1) * width + j] + strip_area(side[i - 1], side[i], crease[j], h, reach, midpoints);
                    if (next < c) c = next, along_side[i * width + j] = 1;
                }
                if (j > 0 && i > 0 && i < m && cost[i * width + j - 1] < inf) {  // side[0], side[m] are on the crease
                    const double next = cost[i * width + j - 1] + strip_area(side[i], crease[j], crease[j - 1], h, reach, midpoints);
                    if (next < c) c = next, along_side[i * width + j] = 0;
                }
            }
        std::size_t i = m, j = n - 1;
        if (cost[(m - 1) * width + n] < cost[m * width + n - 1]) i = m - 1, j = n;
        if (!(cost[i * width + j] < inf)) return false;
        std::vector<Tri> triangles;
        while (i + j > 1) {
            if (along_side[i * width + j]) triangles.push_back({side[i - 1], side[i], crease[j]}), --i;
            else triangles.push_back({side[i], crease[j], crease[j - 1]}), --j;
        }
        for (std::size_t t = 1; t < triangles.size(); ++t)  // neighbours in the strip share a rung
            if (!(dot(area_normal(triangles[t - 1]), area_normal(triangles[t])) > 0)) return false;
        out.insert(out.end(), triangles.begin(), triangles.end());
        return true;
    }

    /// The `query`'s cells to refine, on the mesh as it would be (`triangles`: the
    /// marching-tetrahedra ones kept, those of the redone patches from `first_redone` on):
    /// round each crossing that is not a vertex and is more than half a cell from it (where a
    /// gap's block or a cell failed, the marching-tetrahedra surface cuts the edge there;
    /// distances are sought within two cells, farther is infinity: a kept triangle lies in its
    /// cell, `removed`: the original triangles redone, `patch_of`: a cell's original ones), and
    /// the thin cells whose point it leaves on the wrong side. (The crossings left off the
    /// finished mesh are counted by the cover pass, on the mesh as written.)
    void find_cells_to_refine(const std::vector<Tri>& triangles, std::size_t first_redone, const std::vector<char>& removed,
                              const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of,
                              RefineQuery& query) const {
        const double h = lattice_h();
        std::vector<char> used(positions_.size(), 0);
        for (const Tri& t : triangles)
            for (uint32_t v : t) used[v] = 1;
        auto cell_of = [&](double c, int a) {
            return std::clamp(long(std::floor((c - min_[a]) / step_[a])), 0L, long(cells_[a]) - 1);
        };
        std::vector<Vec> left;
        for (const Crossing& c : crossings_)
            if (!used[c.vertex]) left.push_back(positions_[c.vertex]);
        if (left.empty() && query.thin.empty()) return;
        std::unordered_map<uint64_t, std::vector<uint32_t>> redone;  // a cell → the redone triangles meeting it
        for (std::size_t t = first_redone; t < triangles.size(); ++t) {
            const Vec &p = positions_[triangles[t][0]], &q = positions_[triangles[t][1]], &r = positions_[triangles[t][2]];
            long lo[3], hi[3];  // the cells it meets, not those it only touches (most vertices are on cell edges)
            for (int a = 0; a < 3; ++a) {
                lo[a] = cell_of(std::min({p[a], q[a], r[a]}) + 1e-9 * h, a);
                hi[a] = std::max(lo[a], cell_of(std::max({p[a], q[a], r[a]}) - 1e-9 * h, a));
            }
            for (long z = lo[2]; z <= hi[2]; ++z)
                for (long y = lo[1]; y <= hi[1]; ++y)
                    for (long x = lo[0]; x <= hi[0]; ++x) redone[cell_id(uint64_t(x), uint64_t(y), uint64_t(z))].push_back(uint32_t(t));
        }
        struct NearTriangle {
            Tri corners;
            bool redone;  ///< by this pass, not marching tetrahedra's
        };
        std::unordered_map<uint64_t, std::vector<NearTriangle>> near;  // a cell looked in → the triangles meeting it
        auto in_cell = [&](uint64_t id) -> const std::vector<NearTriangle>& {
            const auto [it, fresh] = near.try_emplace(id);
            if (fresh) {
                if (const auto patch = patch_of(id))
                    for (uint32_t t : *patch)
                        if (!removed[t]) it->second.push_back({mesh_.triangles[t], false});
                if (const auto r = redone.find(id); r != redone.end())
                    for (uint32_t t : r->second) it->second.push_back({triangles[t], true});
            }
            return it->second;
        };
        // The nearest triangle within `radius` cells of q's cell: exact up to `radius` cells away.
        auto nearest = [&](const Vec& q, long radius) {
            double distance = std::numeric_limits<double>::infinity();
            long lo[3], hi[3];
            for (int a = 0; a < 3; ++a)
                lo[a] = std::max(cell_of(q[a], a) - radius, 0L), hi[a] = std::min(cell_of(q[a], a) + radius, long(cells_[a]) - 1);
            for (long z = lo[2]; z <= hi[2]; ++z)
                for (long y = lo[1]; y <= hi[1]; ++y)
                    for (long x = lo[0]; x <= hi[0]; ++x)
                        for (const NearTriangle& t : in_cell(cell_id(uint64_t(x), uint64_t(y), uint64_t(z))))
                            distance = std::min(distance, point_triangle_distance(q, positions_[t.corners[0]], positions_[t.corners[1]],
                                                                                  positions_[t.corners[2]]));
            return distance;
        };
        for (const Vec& q : left) {
            double distance = nearest(q, 1);
            if (distance > h) distance = nearest(q, 2);
            if (!(distance <= 0.5 * h))
                for (uint64_t id : cells_around(q)) query.refine.push_back(id);
        }
        // Which side of the finished mesh p is on, by the triangles nearest it within a cell
        // (their normals summed where they meet at the nearest point: not those as near at
        // another point, whose normals may cancel, as round a tube's axis); on it counts as
        // either. `redone_nearest`: one of those is this pass's, not marching tetrahedra's.
        auto inside_mesh = [&](const Vec& p, bool& inside, double& distance, bool& redone_nearest) {
            const std::array<long, 3> c{cell_of(p[0], 0), cell_of(p[1], 1), cell_of(p[2], 2)};
            double best = std::numeric_limits<double>::infinity();
            Vec closest{};
            struct Candidate {
                double distance;
                Vec point;
                NearTriangle triangle;
            };
            std::vector<Candidate> candidates;
            for (long z = std::max(c[2] - 1, 0L); z <= std::min(c[2] + 1, long(cells_[2]) - 1); ++z)
                for (long y = std::max(c[1] - 1, 0L); y <= std::min(c[1] + 1, long(cells_[1]) - 1); ++y)
                    for (long x = std::max(c[0] - 1, 0L); x <= std::min(c[0] + 1, long(cells_[0]) - 1); ++x)
                        for (const NearTriangle& t : in_cell(cell_id(uint64_t(x), uint64_t(y), uint64_t(z)))) {
                            const Tri& corners = t.corners;
                            const Vec q = closest_point_on_triangle(p, positions_[corners[0]], positions_[corners[1]], positions_[corners[2]]);
                            const double d = norm(sub(p, q));
                            candidates.push_back({d, q, t});
                            if (d < best) best = d, closest = q;
                        }
            distance = best;
            if (candidates.empty()) return false;
            Vec normal{0, 0, 0};
            redone_nearest = false;
            for (const Candidate& candidate : candidates) {
                if (norm(sub(candidate.point, closest)) > 1e-9 * h) continue;
                const Tri& corners = candidate.triangle.corners;
                redone_nearest = redone_nearest || candidate.triangle.redone;
                const Vec n = cross(sub(positions_[corners[1]], positions_[corners[0]]), sub(positions_[corners[2]], positions_[corners[0]]));
                const double length = norm(n);
                if (length > 0)
                    for (int a = 0; a < 3; ++a) normal[a] += n[a] / length;
            }
            inside = dot(sub(p, closest), normal) < 0;
            return true;
        };
        for (const ThinPart& part : query.thin) {
            // Where the pass put the part's edges back, the mesh has its point on the side
            // the field says, or a hair across a face it put back; elsewhere marching
            // tetrahedra's surface cuts it off, however near it passes (Chainik at 64
            // nodes: 0.05 cells from a cell's centre 0.5 cells deep in a slab whose
            // surfaces it joins across).
            bool inside = false, redone_nearest = false;
            double distance = 0;
            if (!inside_mesh(part.point, inside, distance, redone_nearest) ||
                (inside != part.inside && (distance > kThinOffMesh * h || !redone_nearest)))
                query.refine.push_back(part.cell);
        }
        std::sort(query.refine.begin(), query.refine.end());
        query.refine.erase(std::unique(query.refine.begin(), query.refine.end()), query.refine.end());
        for (const auto& [id, apex] : apex_)
            if (used[apex] && apex_equations_.at(id).size() >= 3) query.keep.push_back(id);
        for (const auto& [id, cells] : groups_) query.keep.insert(query.keep.end(), cells.begin(), cells.end());
        query.keep.insert(query.keep.end(), banded_.begin(), banded_.end());
        std::sort(query.keep.begin(), query.keep.end());
        query.keep.erase(std::unique(query.keep.begin(), query.keep.end()), query.keep.end());
    }

    /// Two of the patch's vertex normals more than ~26° apart.
    bool normals_disagree(const std::vector<uint32_t>& patch) const {
        std::vector<uint32_t> vertices;
        for (uint32_t t : patch)
            for (uint32_t v : mesh_.triangles[t]) vertices.push_back(v);
        std::sort(vertices.begin(), vertices.end());
        vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
        for (std::size_t i = 0; i < vertices.size(); ++i)
            for (std::size_t j = i + 1; j < vertices.size(); ++j)
                if (dot(mesh_.normals[vertices[i]], mesh_.normals[vertices[j]]) < kFeatureCosine) return true;
        return false;
    }

    /// The operations whose two operands both reach zero in the cell (first-order estimate).
    /// With `at_corners`, an operand also counts when the cell's corners show it reaching zero
    /// (an exact zero, both signs, or the end of its domain: finite at some, NaN at others),
    /// where the estimate cannot: a power below 1 at its root (X^0.2 at X = 0 estimates 5X,
    /// its slope infinite there).
    std::vector<int> vanishing_operations(const Cell& cell, bool at_corners = false) {
        Vec centre;
        for (int a = 0; a < 3; ++a) centre[a] = (cell.lo[a] + cell.hi[a]) / 2;
        const double half_diagonal = norm(sub(cell.hi, cell.lo)) / 2;
        const auto& ops = field_.operations();
        std::vector<char> by_corners;  // per operation: both operands reach zero at the corners
        if (at_corners) {
            std::vector<std::array<bool, 4>> seen(2 * ops.size());  // per operand: zero, +, −, NaN
            for (int corner = 0; corner < 8; ++corner) {
                Vec p;
                for (int a = 0; a < 3; ++a) p[a] = corner >> a & 1 ? cell.hi[a] : cell.lo[a];
                field_.at(p);
                for (std::size_t k = 0; k < ops.size(); ++k)
                    for (int side = 0; side < 2; ++side) {
                        const double v = field_.value(side ? ops[k].b : ops[k].a);
                        seen[2 * k + std::size_t(side)][v == 0 ? 0 : v > 0 ? 1 : v < 0 ? 2 : 3] = true;
                    }
            }
            auto reaches = [](const std::array<bool, 4>& s) { return s[0] || (s[1] && s[2]) || ((s[1] || s[2]) && s[3]); };
            for (std::size_t k = 0; k < ops.size(); ++k) by_corners.push_back(reaches(seen[2 * k]) && reaches(seen[2 * k + 1]));
        }
        field_.at(centre);
        auto reaches_zero = [&](int i) {
            // Zero at the centre reaches zero, whatever its gradient: an R-operation's is NaN on
            // its own edge (√(a² + b²) at a = b = 0), where a corner at the centre of its cell
            // lies (new_euclid's prism apex meeting its sphere at (0, 4, 2) on 96 nodes).
            if (field_.value(i) == 0) return true;
            const double g = norm(field_.gradient(i));
            return std::isfinite(g) && std::fabs(field_.value(i)) <= kReachFactor * g * half_diagonal;
        };
        std::vector<int> out;
        for (std::size_t k = 0; k < ops.size(); ++k)
            if ((reaches_zero(ops[k].a) && reaches_zero(ops[k].b)) || (at_corners && by_corners[k])) out.push_back(int(k));
        return out;
    }

    /// The model is zero at p to round-off (the edge of operation `k` is on the surface there,
    /// not hidden inside or outside by the operations above it).
    bool on_boundary(const Vec& p, int k, double h) {
        field_.at(p);
        const auto& op = field_.operations()[k];
        const double ga = norm(field_.gradient(op.a)), gb = norm(field_.gradient(op.b));
        const double scale = 1 + (std::isfinite(ga) ? ga : 0) + (std::isfinite(gb) ? gb : 0);
        if (!(std::fabs(field_.value(0)) <= 1e-8 * h * scale)) return false;
        if (field_.value(0) != 0) return true;
        // Exactly zero: also where two parts of the solid are joined on a plane, inside it
        // (zero_inside); the edges of the operations there are not on its surface.
        double probes[kZeroProbes];
        for (int k = 0; k < kZeroProbes; ++k) {
            const Vec offset = zero_probe(k);
            field_.at({p[0] + offset[0] * h, p[1] + offset[1] * h, p[2] + offset[2] * h});
            probes[k] = field_.value(0);
        }
        field_.at(p);
        return !zero_inside(probes);
    }

    static uint64_t visit_key(uint64_t cell, int k) { return cell * 4096 + uint64_t(k % 4096); }

    std::array<uint64_t, 2> cells_of_face(uint64_t face) const {
        const uint64_t lower = face / 3;
        return {lower, lower + stride(int(face % 3))};
    }

    /// The cells whose boundary holds crossing c: those of its chosen face, or all around a
    /// marching-tetrahedra vertex it is.
    std::vector<uint64_t> cells_sharing(const Crossing& c) const {
        if (c.on_mesh_vertex) return cells_around(positions_[c.vertex]);
        const auto two = cells_of_face(c.face);
        return {two[0], two[1]};
    }

    /// The crossings (alive) on the faces of cell `id`.
    std::vector<int> crossings_in(uint64_t id) const {
        std::vector<int> out;
        const auto c = coords(id);
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side) {
                if (side == 0 && c[a] == 0) continue;
                const uint64_t face = (side == 0 ? id - stride(a) : id) * 3 + uint64_t(a);
                const auto it = face_crossings_.find(face);
                if (it == face_crossings_.end()) continue;
                for (int x : it->second)
                    if (crossings_[x].alive && (crossings_[x].face == face || crossings_[x].on_mesh_vertex)) out.push_back(x);
            }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    Vec edge_normal(const Vec& p, const std::vector<int>& equations) {
        field_.at(p);
        Vec n{0, 0, 0};
        for (int e : equations) {
            const Vec g = field_.gradient(e);
            const double l = norm(g);
            if (!(l > 0) || !finite(g)) continue;
            for (int a = 0; a < 3; ++a) n[a] -= g[a] / l;
        }
        const double l = norm(n);
        if (!(l > 0)) return {0, 0, 1};
        return {n[0] / l, n[1] / l, n[2] / l};
    }

    /// The crossing of operation k's edge at q (on a face): an existing one there, or a new one
    /// on every face that holds q.
    std::pair<int, bool> crossing_at(int k, const Vec& q, double h) {
        const std::vector<uint64_t> faces = faces_around(q);
        for (uint64_t face : faces) {
            const auto it = face_crossings_.find(face);
            if (it == face_crossings_.end()) continue;
            for (int x : it->second)
                if (crossings_[x].operation == k && norm(sub(positions_[crossings_[x].vertex], q)) <= 1e-6 * h)
                    return {x, true};
        }
        const auto& op = field_.operations()[k];
        crossings_.push_back({uint32_t(positions_.size()), k, faces.empty() ? 0 : faces[0]});
        positions_.push_back(q);
        normals_.push_back(edge_normal(q, {op.a, op.b}));
        for (uint64_t face : faces) face_crossings_[face].push_back(int(crossings_.size() - 1));
        return {int(crossings_.size() - 1), false};
    }

    /// Joins crossings a and b in the cells that hold both (the one the curve passed, or, for
    /// a piece along a grid edge, the cells around it that have triangles).
    void add_link(int a, int b) {
        const std::pair<int, int> link{std::min(a, b), std::max(a, b)};
        if (std::find(partners_[a].begin(), partners_[a].end(), b) == partners_[a].end())
            partners_[a].push_back(b), partners_[b].push_back(a);
        for (uint64_t cell : cells_holding(positions_[crossings_[a].vertex], positions_[crossings_[b].vertex])) {
            if (has_patch_ && !has_patch_(cell)) continue;
            auto& list = links_[cell];
            if (std::find(list.begin(), list.end(), link) == list.end()) list.push_back(link);
        }
    }

    /// Removes the link between crossings a and b (from both partner lists and every cell's).
    void drop_link(int a, int b) {
        const std::pair<int, int> link{std::min(a, b), std::max(a, b)};
        for (auto& [cell, list] : links_) std::erase(list, link);
        std::erase(partners_[a], b);
        std::erase(partners_[b], a);
    }

    /// Follows operation k's edge curve from p (in `cell`, on the curve) along ±(∇a × ∇b),
    /// a quarter cell per predictor step and Newton back onto the curve, recording where it
    /// crosses cell faces and linking consecutive crossings in the cell between them. Stops
    /// at a crossing already recorded (the curve is closed or met another trace), where the
    /// curve leaves the surface (a corner: the cell is remembered), at the domain's faces, or
    /// where the operands' gradients turn parallel. Returns the first crossing, or -1.
    int walk(int k, uint64_t cell, Vec p, int direction) {
        const auto& op = field_.operations()[k];
        int first = -1, previous = -1;
        visited_.insert(visit_key(cell, k));
        int steps_here = 0;  // a curve that stays in one cell that long is a small loop
        for (int steps = 0; steps < kMaxTraceSteps && ++steps_here <= kMaxStepsInCell; ++steps) {
            const Cell box = cell_box(cell);
            const double h = box.h;
            field_.at(p);
            const Vec ga = field_.gradient(op.a), gb = field_.gradient(op.b);
            const Vec t = cross(ga, gb);
            const double lt = norm(t);
            if (!(lt > kIndependence * norm(ga) * norm(gb)) || !finite(t)) break;
            // A step past a corner (another operand takes over there) finds no point of this
            // curve: shorter ones still reach the face before it, or end in the corner's cell.
            Vec next = p;
            double step = 0.25 * h;
            bool solved = false;
            for (int tries = 0; tries < kStepHalvings && !solved; ++tries) {
                if (tries > 0) step /= 2;
                next = p;
                for (int a = 0; a < 3; ++a) next[a] += double(direction) * step * t[a] / lt;
                solved = solve_feature(field_, {op.a, op.b}, 2, next, h, h);
            }
            if (!solved) {
                end_cells_.insert(cell);
                break;
            }
            next = snapped(next);  // a curve along a grid edge stays on it, in the cell
            if (norm(sub(next, p)) < 0.04 * step) break;
            if (box.contains(next, 0)) {
                if (!on_boundary(next, k, h)) {
                    end_cells_.insert(cell);
                    return first;
                }
                p = next;
                continue;
            }
            // Left the cell: the face planes the step passes, nearest first, and the exact
            // crossing on the first one the curve goes through.
            std::vector<std::tuple<double, int, int>> exits;  // (fraction of the step, axis, side)
            for (int a = 0; a < 3; ++a) {
                if (next[a] > box.hi[a]) exits.emplace_back((box.hi[a] - p[a]) / (next[a] - p[a]), a, 1);
                if (next[a] < box.lo[a]) exits.emplace_back((box.lo[a] - p[a]) / (next[a] - p[a]), a, 0);
            }
            std::sort(exits.begin(), exits.end());
            bool crossed = false, ends = false;
            int axis = 0, side = 0;
            Vec q{};
            for (const auto& [fraction, a, s] : exits) {
                Vec x = p;
                for (int b = 0; b < 3; ++b) x[b] += fraction * (next[b] - p[b]);
                const double plane = s ? box.hi[a] : box.lo[a];
                if (!solve_feature(field_, {op.a, op.b}, 2, x, h, h, a, plane)) continue;
                x = snapped(x);  // on a grid edge or node: exactly there, for every cell around it
                bool on_face = true;
                for (int b = 0; b < 3; ++b)
                    if (b != a && (x[b] < box.lo[b] || x[b] > box.hi[b])) on_face = false;
                if (!on_face) continue;
                if (!on_boundary(x, k, h)) {
                    ends = true;
                    break;
                }
                crossed = true, axis = a, side = s, q = x;
                break;
            }
            if (ends) {
                end_cells_.insert(cell);
                return first;
            }
            if (!crossed) break;
            const auto c = coords(cell);
            if (side == 0 ? c[axis] == 0 : c[axis] + 1 >= uint64_t(cells_[axis])) break;  // the domain's face
            // The cell the curve enters: across the face, and across each other face q lies on
            // (a crossing at a grid edge or node) that the curve leaves by; a curve running in
            // a grid plane stays on the side it came from.
            std::array<long, 3> to{long(c[0]), long(c[1]), long(c[2])};
            to[axis] += side ? 1 : -1;
            field_.at(q);
            const Vec tangent = cross(field_.gradient(op.a), field_.gradient(op.b));
            const double length = norm(tangent);
            bool leaves_domain = false;
            for (int b = 0; b < 3; ++b) {
                if (b == axis) continue;
                const double along = direction * tangent[b];
                if (q[b] == box.lo[b] && along < -1e-6 * length) --to[b];
                if (q[b] == box.hi[b] && along > 1e-6 * length) ++to[b];
                leaves_domain |= to[b] < 0 || to[b] >= cells_[b];
            }
            if (leaves_domain) break;
            const uint64_t neighbour = cell_id(uint64_t(to[0]), uint64_t(to[1]), uint64_t(to[2]));
            const auto [id, existed] = crossing_at(k, q, h);
            if (previous >= 0) add_link(previous, id);
            else if (first < 0) first = id;
            if (existed) return first;
            // A cap's rim into a cell with no triangles goes where the solid is thinner than a
            // cell inside the domain's outer layer, whose nodes count as outside: no mesh there.
            if (is_cap_[std::size_t(k)] && has_patch_ && !has_patch_(neighbour)) return first;
            cell = neighbour;
            previous = id;
            p = q;
            steps_here = 0;
            visited_.insert(visit_key(cell, k));
        }
        return first;
    }

    /// The axis of the grid line p and q both lie on (the same grid plane in the two other
    /// axes), or -1.
    int grid_edge_axis(const Vec& p, const Vec& q) const {
        if (shared_grid_planes(p, q) != 2) return -1;
        for (int axis = 0; axis < 3; ++axis)
            if (!same_grid_plane(p, q, axis)) return axis;
        return -1;
    }

    /// How many grid planes p lies on (two on a grid edge, three at a node).
    int grid_planes_holding(const Vec& p) const {
        int count = 0;
        for (int axis = 0; axis < 3; ++axis) count += plane_of(p, axis) >= 0;
        return count;
    }

    /// Whether p and q lie on the same grid plane across `axis`.
    bool same_grid_plane(const Vec& p, const Vec& q, int axis) const {
        const long k = plane_of(p, axis);
        return k >= 0 && k == plane_of(q, axis);
    }

    /// How many grid planes p and q both lie on.
    int shared_grid_planes(const Vec& p, const Vec& q) const {
        int shared = 0;
        for (int axis = 0; axis < 3; ++axis) shared += same_grid_plane(p, q, axis);
        return shared;
    }

    /// Whether cell id is already redone some other way: a corner's fan, a group, a wedge's
    /// block, or the cell of a corner a wedge's tree holds as a tip (its fan again if the
    /// wedge fails).
    bool taken(uint64_t id) const {
        if (groups_.count(id) || apex_.count(id) || wedge_of_.count(id)) return true;
        for (const auto& [tip, corner] : corner_tips_)
            if (corner.first == id) return true;
        return false;
    }

    /// A piece of edge in a grid plane with the solid on both sides of it (the pentagon
    /// prism's vertical edges at x = 0 on cells of 0.5, along a grid edge; the FLOZ3 plate's
    /// 39° edge in y = 0 on 15 nodes in y, across a face): the two cells beside that plane
    /// both have triangles, and the piece lies on the face between them, so neither may join
    /// it alone (marching tetrahedra's segment on that face, a thousandth of a cell off, is
    /// what the other cell meets). Their patches are redone together instead, the face
    /// between them inside, as for a corner on the lattice (groups_).
    void plan_edge_groups(const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of) {
        std::map<uint64_t, std::vector<uint64_t>> planned;
        std::set<uint64_t> refused;  // wanted by two different groups: left to themselves
        for (const auto& [id, links] : links_)
            for (const auto& [a, b] : links) {
                const Vec &p = positions_[crossings_[a].vertex], &q = positions_[crossings_[b].vertex];
                const int shared = shared_grid_planes(p, q);
                // Across a face, only a piece whose ends are on grid edges: ends inside the face
                // would be inside the joined cells, off their joined boundary.
                if (shared == 0) continue;
                if (shared == 1 && (grid_planes_holding(p) < 2 || grid_planes_holding(q) < 2)) continue;
                std::vector<uint64_t> cells = cells_holding(p, q);
                std::erase_if(cells, [&](uint64_t cell) { return has_patch_ && !has_patch_(cell); });
                if (cells.size() != 2) continue;
                std::sort(cells.begin(), cells.end());
                const auto c0 = coords(cells[0]), c1 = coords(cells[1]);
                int differ = 0;
                for (int axis = 0; axis < 3; ++axis) differ += c0[axis] != c1[axis];
                if (differ != 1) continue;  // across the grid edge: no face between them
                for (uint64_t cell : cells) {
                    const auto it = planned.find(cell);
                    if (it != planned.end() && it->second != cells) refused.insert(cell);
                    planned[cell] = cells;
                }
            }
        std::vector<std::pair<uint64_t, std::vector<uint64_t>>> chosen;
        for (const auto& [cell, cells] : planned) {
            bool free = true;
            for (uint64_t g : cells) free &= !refused.count(g) && !taken(g);
            if (free) chosen.emplace_back(cell, cells);
        }
        for (auto& [cell, cells] : chosen) groups_[cell] = std::move(cells);
        // Each end of such a piece sits a thousandth of a cell from marching tetrahedra's vertex
        // v on the face between the two cells. It goes into a segment beside v in the grid
        // plane across the piece (not one on the face between them, which the group holds
        // inside), and the short edge from v to it falls to the side of the other segment: it
        // must be the side whose surface that edge does not stand up from (seen along that
        // side's normal a triangle on it has no area: the prism's x = 0 edge at y = -3).
        std::set<int> placed;
        for (const auto& [cell, cells] : groups_) {
            if (apex_.count(cell) || cells.size() != 2) continue;
            for (uint64_t g : cells)
                if (const auto links = links_.find(g); links != links_.end())
                    for (const auto& [a, b] : links->second) {
                        const int along = grid_edge_axis(positions_[crossings_[a].vertex], positions_[crossings_[b].vertex]);
                        if (along < 0) continue;
                        for (int x : {a, b})
                            if (placed.insert(x).second) place_across_piece(x, along, cells, patch_of);
                    }
        }
    }

    /// A cell whose patch is not one disc cannot take a link from one of its pieces to another:
    /// where the solid in it is a strip along one face, across that face's Kuhn diagonal,
    /// marching tetrahedra make two sheets, one at each end of the strip (the FLOZ3 plate's
    /// 70.5° edge at 33 nodes, 1/12 of a cell above a grid plane, runs from one to the other).
    /// Both sheets come through that face, so with the cell beyond it the joined patch is one
    /// disc: the two cells are redone together, as an edge group's are.
    void plan_sheet_groups(const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of) {
        for (const auto& [id, links] : links_) {
            if (links.empty() || taken(id)) continue;
            const auto patch = patch_of(id);
            std::vector<uint32_t> loop;
            if (!patch || boundary_loop(*patch, cell_box(id), loop)) continue;
            for (uint64_t other : face_neighbours(id)) {  // the first that makes one disc
                if (taken(other)) continue;
                const auto more = patch_of(other);
                if (!more) continue;
                std::vector<uint32_t> joined = *patch;
                joined.insert(joined.end(), more->begin(), more->end());
                const std::vector<uint64_t> cells{std::min(id, other), std::max(id, other)};
                if (!boundary_loop(joined, joined_box(cells), loop)) continue;
                groups_[id] = cells;
                groups_[other] = cells;
                break;
            }
        }
    }

    /// Crossing x at an end of an edge group's piece along axis `along` (cells: the two beside
    /// it) put into the segment of one cell's ring at the marching-tetrahedra vertex next to it
    /// in the grid plane across the piece: the cell whose surface is the more perpendicular to
    /// the short edge from that vertex, which then falls to the other cell.
    void place_across_piece(int x, int along, const std::vector<uint64_t>& cells,
                            const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of) {
        Crossing& c = crossings_[x];
        if (!c.alive || c.on_mesh_vertex || c.segment.first == UINT32_MAX) return;
        const Vec q = positions_[c.vertex];
        const double h = lattice_h(), tolerance = 1e-9 * h;
        const auto c0 = coords(cells[0]), c1 = coords(cells[1]);
        int between = 0;  // the axis of the face between the two cells
        for (int a = 0; a < 3; ++a)
            if (c0[a] != c1[a]) between = a;
        std::vector<uint32_t> rings[2];
        Vec normal[2];
        for (int i = 0; i < 2; ++i) {
            const auto patch = patch_of(cells[i]);
            if (!patch || !boundary_loop(*patch, cell_box(cells[i]), rings[i])) return;
            normal[i] = {0, 0, 0};
            for (uint32_t t : *patch) {
                const Tri& tri = mesh_.triangles[t];
                const Vec n = cross(sub(mesh_.vertices[tri[1]], mesh_.vertices[tri[0]]),
                                    sub(mesh_.vertices[tri[2]], mesh_.vertices[tri[0]]));
                for (int a = 0; a < 3; ++a) normal[i][a] += n[a];
            }
            const double l = norm(normal[i]);
            if (!(l > 0)) return;
            for (double& n : normal[i]) n /= l;
        }
        // v: on both rings, on the face between the cells and the plane across the piece.
        uint32_t v = UINT32_MAX;
        double nearest = 1e-2 * h;
        for (uint32_t r : rings[0]) {
            const Vec& at = positions_[r];
            if (std::fabs(at[between] - q[between]) > tolerance || std::fabs(at[along] - q[along]) > tolerance) continue;
            if (std::find(rings[1].begin(), rings[1].end(), r) == rings[1].end()) continue;
            if (norm(sub(at, q)) < nearest) nearest = norm(sub(at, q)), v = r;
        }
        if (v == UINT32_MAX || !(nearest > 0)) return;
        const Vec d = sub(positions_[v], q);
        // Into the ring of the cell whose normal is the more aligned with d.
        // A tie (the prism's corner (-3.5, 0.5) between two 45° faces) goes to the upper cell, the
        // same for every piece of the edge: round-off deciding it would put the two ends' short
        // edges on different sides, and the sides' triangles would cross.
        const double aligned[2] = {std::fabs(dot(normal[0], d)), std::fabs(dot(normal[1], d))};
        const int into = aligned[0] > aligned[1] + 1e-6 * norm(d) ? 0 : 1;
        const std::vector<uint32_t>& ring = rings[into];
        const std::size_t n = ring.size();
        const std::size_t at = std::size_t(std::find(ring.begin(), ring.end(), v) - ring.begin());
        const Cell box = cell_box(cells[into]);
        const auto cc = coords(cells[into]);
        for (const uint32_t r : {ring[(at + n - 1) % n], ring[(at + 1) % n]}) {
            if (std::fabs(positions_[r][along] - q[along]) > tolerance) continue;
            const bool upper = q[along] == box.hi[along];
            if (!upper && q[along] != box.lo[along]) return;
            if (upper ? cc[along] + 1 >= uint64_t(cells_[along]) : cc[along] == 0) return;  // the domain's face
            c.segment = {std::min(v, r), std::max(v, r)};
            c.face = (upper ? cells[into] : cells[into] - stride(along)) * 3 + uint64_t(along);
            return;
        }
    }

    /// A corner in cell `id`: three independent operands of the operations that vanish there
    /// are zero together, inside the cell and on the surface.
    void find_corner(uint64_t id) {
        if (apex_.count(id) || tried_corner_.count(id)) return;
        tried_corner_.insert(id);
        const Cell cell = cell_box(id);
        std::vector<int> candidates = vanishing_operations(cell);
        if (candidates.size() < 2) candidates = vanishing_operations(cell, true);
        if (candidates.size() < 2) return;
        const auto& ops = field_.operations();
        std::vector<int> equations, later;
        for (int k : candidates)
            for (int e : {ops[k].a, ops[k].b}) {
                std::vector<int>& list = field_.operation_of(e) >= 0 ? later : equations;
                if (std::find(list.begin(), list.end(), e) == list.end()) list.push_back(e);
            }
        equations.insert(equations.end(), later.begin(), later.end());
        Vec p;
        for (int a = 0; a < 3; ++a) p[a] = (cell.lo[a] + cell.hi[a]) / 2;
        if (!solve_feature(field_, equations, 3, p, cell.h, 2 * cell.h) || !cell.contains(p, 1e-9 * cell.h)) return;
        p = snapped(p);
        if (!cell.contains(p, 1e-12 * cell.h)) return;
        bool on_surface = false;
        for (int k : candidates) on_surface |= on_boundary(p, k, cell.h);
        if (!on_surface) return;
        // On a grid face, edge or node the corner belongs to every cell around it that has
        // triangles (one vertex for all); a traced edge's crossing there is the corner itself.
        uint32_t vertex = UINT32_MAX;
        for (const auto& [other, apex] : apex_)
            if (norm(sub(positions_[apex], p)) <= 1e-9 * cell.h) vertex = apex;
        for (uint64_t face : faces_around(p)) {
            const auto it = face_crossings_.find(face);
            if (it == face_crossings_.end()) continue;
            for (int x : it->second)
                if (norm(sub(positions_[crossings_[x].vertex], p)) <= 1e-9 * cell.h) crossings_[x].alive = false;
        }
        std::vector<uint64_t> cells;
        for (uint64_t at : cells_around(p)) {
            if (apex_.count(at) || (has_patch_ && !has_patch_(at))) continue;
            if (vertex == UINT32_MAX) {
                vertex = uint32_t(positions_.size());
                positions_.push_back(p);
                normals_.push_back(edge_normal(p, equations));
            }
            apex_[at] = vertex;
            apex_equations_[at] = equations;
            tried_corner_.insert(at);
            cells.push_back(at);
        }
        if (cells.size() > 1)
            for (uint64_t at : cells) groups_[at] = cells;
        if (cells.empty() && vertex == UINT32_MAX) {  // a tip the lattice misses (wedges, below)
            tips_.push_back(uint32_t(positions_.size()));
            positions_.push_back(p);
            normals_.push_back(edge_normal(p, equations));
        }
    }

    /// Drops a link the trace drew across a corner: where one operation's zero curve has a kink
    /// at the corner (two edges of the solid: the FLOZ3 plate's edges from (-0.85, -1, -1.15)
    /// up its vertical face and along its slab face are both where the slab face meets the
    /// rest), the trace follows it across and joins the two edges' crossings by a chord that
    /// cuts the corner off; 0.002 below a face (57 nodes) that chord lay on the face, where
    /// the cell above cannot take it either. The corner's fan joins each of them to it.
    void cut_chains_at_corners() {
        const double h = lattice_h();
        for (const auto& [id, apex] : apex_) {
            const Vec& p = positions_[apex];
            field_.at(p);
            const std::vector<int> here = crossings_in(id);
            for (int a : here) {
                const auto& op = field_.operations()[std::size_t(crossings_[a].operation)];
                if (!vanishes(field_, op.a, h) || !vanishes(field_, op.b, h)) continue;
                const std::vector<int> partners = partners_[a];
                for (int b : partners) {
                    if (b < a || crossings_[b].operation != crossings_[a].operation ||
                        !std::binary_search(here.begin(), here.end(), b))
                        continue;
                    drop_link(a, b);
                }
            }
        }
    }

    /// A corner in a cell with triangles at the end of an edge whose cells have none (the FLOZ3
    /// plate's 70.5° edge y = -1 at 21 nodes, 0.05 of a cell below a grid plane): that edge's
    /// tree would take a block around the corner's cell, which the corner's fan keeps out, so
    /// the joined patch would have a hole. Such a corner (a crossing with no segment in a cell
    /// touching its own, the plate at 61 nodes, or on its faces) joins the tree as a tip
    /// instead, its cell in the block (the edges from it are pieces of their own there);
    /// restored to its fan if no block of the tree can be redone.
    void corners_into_trees() {
        std::map<uint64_t, std::vector<Vec>> beside;  // a corner's cell → the crossings with no segment next to it
        for (std::size_t x = 0; x < crossings_.size(); ++x)
            if (!crossings_[x].alive && !nodes_passed_.count(int(x)))
                for (uint64_t id : cells_around(positions_[crossings_[x].vertex]))
                    for (const auto& [corner, apex] : apex_)
                        if (touching(id, corner)) beside[corner].push_back(positions_[crossings_[x].vertex]);
        std::map<uint32_t, std::vector<uint64_t>> cells_of;
        for (const auto& [id, apex] : apex_) cells_of[apex].push_back(id);
        for (const auto& [vertex, cells] : cells_of) {
            if (cells.size() != 1) continue;  // a corner on the lattice, fanned over its cells
            const uint64_t id = cells.front();
            const auto it = beside.find(id);
            if (it == beside.end() || std::none_of(it->second.begin(), it->second.end(), [&](const Vec& p) {
                    return norm(sub(p, positions_[vertex])) > 1e-9 * lattice_h();  // not the corner itself
                }))
                continue;
            corner_tips_[-1 - int(tips_.size())] = {id, vertex};
            tips_.push_back(vertex);
            apex_.erase(id);
        }
    }

    /// The corners made tips whose tree found no block: back to their fans.
    void restore_unplanned_corners() {
        std::set<int> planned;
        for (const Wedge& wedge : wedges_)
            if (!wedge.cells.empty())
                for (int n : wedge.nodes) planned.insert(n);
        for (const auto& [tip, corner] : corner_tips_)
            if (!planned.count(tip)) apex_[corner.first] = corner.second;
    }

    /// The corners fanned in a cell that wedge w's last joined cells surround (every neighbour
    /// across a face with triangles among them) made tips of its tree, their cells' crossings
    /// on edges through them its links; false if there is none. The joined patch rings such a
    /// cell (the FLOZ3 plate's end face at 31 nodes: its edges run in cells with no triangles
    /// but near the corner (-1.15, 1, -0.85)), so the block cannot be redone without it.
    bool take_in_corners(std::size_t w) {
        Wedge& wedge = wedges_[w];
        if (wedge.around_nodes) return false;
        std::map<uint32_t, int> cells_of;
        for (const auto& [id, apex] : apex_) ++cells_of[apex];
        auto joined = [&](uint64_t id) { return std::binary_search(wedge.cells.begin(), wedge.cells.end(), id); };
        std::vector<uint64_t> taken;
        for (const auto& [id, apex] : apex_) {
            if (cells_of[apex] != 1 || groups_.count(id)) continue;
            bool surrounded = true, beside = false;
            for (uint64_t next : face_neighbours(id)) {
                if (has_patch_ && !has_patch_(next)) continue;
                beside |= joined(next);
                surrounded &= joined(next);
            }
            if (surrounded && beside) taken.push_back(id);
        }
        const double h = lattice_h();
        for (uint64_t id : taken) {
            const uint32_t vertex = apex_[id];
            const int tip = -1 - int(tips_.size());
            corner_tips_[tip] = {id, vertex};
            tips_.push_back(vertex);
            apex_.erase(id);
            wedge.nodes.push_back(tip);
            field_.at(positions_[vertex]);
            for (int x : crossings_in(id)) {
                const auto& op = field_.operations()[std::size_t(crossings_[x].operation)];
                if (tip_crossings_.count(x) || !vanishes(field_, op.a, h) || !vanishes(field_, op.b, h)) continue;
                tip_crossings_[x] = tip;
                crossings_of_tip_[tip].push_back(x);
            }
        }
        return !taken.empty();
    }

    /// Wedge w's corners made tips back to their fans, when no block of it can be redone;
    /// returns their cells.
    std::vector<uint64_t> restore_corners(const Wedge& wedge) {
        std::vector<uint64_t> cells;
        for (int n : wedge.nodes)
            if (const auto it = corner_tips_.find(n); it != corner_tips_.end()) {
                apex_[it->second.first] = it->second.second;
                cells.push_back(it->second.first);
            }
        return cells;
    }

    /// For a cell whose crossings cannot be joined by edges (the boundary split along them
    /// folds, or a corner on a face two cells mesh could not be fanned): a fan from a point of
    /// the edge curve in the cell (Newton from its crossings' mean), so the crossings stay and
    /// the neighbours keep theirs; a failed cell would otherwise undo the whole chain, cell
    /// after cell. Tried once per cell; false if there is no such point.
    bool add_edge_apex(uint64_t id) {
        if (!edge_apex_tried_.insert(id).second) return false;
        const std::vector<int> crossings = crossings_in(id);
        if (crossings.empty()) return false;
        std::map<int, int> count;
        for (int x : crossings) ++count[crossings_[x].operation];
        const int k = std::max_element(count.begin(), count.end(), [](const auto& a, const auto& b) {
                          return a.second < b.second;
                      })->first;
        const Cell cell = cell_box(id);
        Vec p{0, 0, 0};
        for (int x : crossings)
            if (crossings_[x].operation == k)
                for (int a = 0; a < 3; ++a) p[a] += positions_[crossings_[x].vertex][a] / count[k];
        if (count[k] == 1)  // one crossing: from halfway to the cell's centre, not onto the crossing
            for (int a = 0; a < 3; ++a) p[a] = (p[a] + (cell.lo[a] + cell.hi[a]) / 2) / 2;
        const auto& op = field_.operations()[k];
        std::vector<int> equations{op.a, op.b};
        const Vec start = p;
        bool found = solve_feature(field_, equations, 2, p, cell.h, 2 * cell.h) && cell.contains(p, 1e-9 * cell.h);
        if (found) {
            p = snapped(p);
            found = cell.contains(p, 0) && on_boundary(p, k, cell.h);
        }
        if (!found) {
            // The curve only touches the cell (through a grid node or along a grid edge of it):
            // a point of the surface instead, Newton along the gradient from the cell's middle.
            equations = {0};
            for (int a = 0; a < 3; ++a) p[a] = (start[a] + (cell.lo[a] + cell.hi[a]) / 2) / 2;
            for (int iteration = 0; iteration < 40 && !found; ++iteration) {
                field_.at(p);
                const Vec g = field_.gradient(0);
                const double g2 = dot(g, g), f = field_.value(0);
                if (!(g2 > 0) || !std::isfinite(f) || !finite(g)) return false;
                for (int a = 0; a < 3; ++a) p[a] -= f * g[a] / g2;
                found = std::fabs(f) / std::sqrt(g2) <= 1e-12 * cell.h;
            }
            if (!found || !cell.contains(p, -1e-3 * cell.h)) return false;
        }
        for (int x : crossings)
            if (norm(sub(positions_[crossings_[x].vertex], p)) < 1e-3 * cell.h) return false;
        apex_[id] = uint32_t(positions_.size());
        positions_.push_back(p);
        normals_.push_back(edge_normal(p, equations));
        apex_equations_[id] = equations;
        return true;
    }

    /// Where each crossing goes: of the boundary segments of the patches around it that lie on
    /// a face holding it, the nearest, ties broken by the segments' vertices, the same for
    /// every cell. A crossing with none within a cell dies.
    void choose_segments(const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of) {
        std::map<uint64_t, std::optional<std::vector<uint32_t>>> rings;
        auto ring_of = [&](uint64_t id) -> const std::optional<std::vector<uint32_t>>& {
            auto it = rings.find(id);
            if (it != rings.end()) return it->second;
            std::optional<std::vector<uint32_t>> ring;
            if (const auto patch = patch_of(id)) {
                std::vector<uint32_t> loop;
                if (boundary_loop(*patch, cell_box(id), loop)) ring = std::move(loop);
            }
            return rings.emplace(id, std::move(ring)).first->second;
        };
        struct Clone {
            int of;
            uint64_t face;
            std::pair<uint32_t, uint32_t> segment;
            std::vector<uint64_t> cells;  ///< the linked cells it serves
        };
        std::vector<Clone> clones;
        const std::size_t traced = crossings_.size();
        for (std::size_t index = 0; index < traced; ++index) {
            Crossing& x = crossings_[index];
            if (!x.alive) continue;
            const Vec& q = positions_[x.vertex];
            struct Candidate {
                double distance;
                std::pair<uint32_t, uint32_t> segment;
                uint64_t face;
                bool folds;  ///< q put in crosses another segment of the face's ring
                double bend;  ///< its ends' normals' dot product: the surface turns across it
            };
            std::vector<Candidate> candidates;
            double h = 0;
            for (uint64_t id : cells_around(q)) {
                const auto& ring = ring_of(id);
                if (!ring) continue;
                const Cell cell = cell_box(id);
                h = cell.h;
                const double tolerance = 1e-9 * cell.h;
                const auto c = coords(id);
                const std::size_t n = ring->size();
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side) {
                        const double plane = side ? cell.hi[axis] : cell.lo[axis];
                        if (q[axis] != plane) continue;
                        if (side == 0 ? c[axis] == 0 : c[axis] + 1 >= uint64_t(cells_[axis])) continue;
                        const uint64_t face = (side ? id : id - stride(axis)) * 3 + uint64_t(axis);
                        for (std::size_t i = 0; i < n; ++i) {
                            const uint32_t a = std::min((*ring)[i], (*ring)[(i + 1) % n]),
                                           b = std::max((*ring)[i], (*ring)[(i + 1) % n]);
                            const Vec &u = positions_[a], &v = positions_[b];
                            if (std::fabs(u[axis] - plane) > tolerance || std::fabs(v[axis] - plane) > tolerance) continue;
                            const Vec d = sub(v, u);
                            const double s = std::clamp(dot(sub(q, u), d) / dot(d, d), 0.0, 1.0);
                            // A face cut twice (two sheets across it): the crossing may lie beyond
                            // the nearer segment's neighbour, and put in there the face's
                            // boundary would cross itself (build_cell refuses it).
                            const int e = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;
                            auto flat = [&](const Vec& p) { return std::array<double, 2>{p[e], p[w]}; };
                            bool folds = false;
                            for (std::size_t j = 0; j < n && !folds; ++j) {
                                const Vec &f = positions_[(*ring)[j]], &g = positions_[(*ring)[(j + 1) % n]];
                                if (std::fabs(f[axis] - plane) > tolerance || std::fabs(g[axis] - plane) > tolerance) continue;
                                if (std::min((*ring)[j], (*ring)[(j + 1) % n]) == a && std::max((*ring)[j], (*ring)[(j + 1) % n]) == b) continue;
                                folds = segments_cross_2d(flat(u), flat(q), flat(f), flat(g), 1e-12 * h * h) ||
                                        segments_cross_2d(flat(q), flat(v), flat(f), flat(g), 1e-12 * h * h);
                            }
                            candidates.push_back({norm(sub(q, {u[0] + s * d[0], u[1] + s * d[1], u[2] + s * d[2]})), {a, b}, face,
                                                  folds, dot(normals_[a], normals_[b])});
                        }
                    }
            }
            double nearest = std::numeric_limits<double>::infinity();
            for (const Candidate& c : candidates) nearest = std::min(nearest, c.distance);
            // At a marching-tetrahedra vertex to within 1e-6 of a cell (Newton along its edge
            // stops at 1e-7 of it): that vertex is the crossing, moved exactly onto the curve.
            uint32_t at_vertex = UINT32_MAX;
            double closest = 1e-6 * h;
            for (const Candidate& c : candidates)
                for (uint32_t v : {c.segment.first, c.segment.second})
                    if (norm(sub(positions_[v], q)) <= closest) closest = norm(sub(positions_[v], q)), at_vertex = v;
            if (at_vertex != UINT32_MAX) {
                positions_[at_vertex] = q;
                x.vertex = at_vertex;
                x.on_mesh_vertex = true;
                continue;
            }
            // A node the curve passes diagonally is no marching-tetrahedra vertex (theirs
            // sit a thousandth of a cell off it), and put into one face's segment it folds the
            // cells around it (the Steinmetz curve through (0.6, 0.8, 0.8) on cells of 0.2): it
            // goes into no segment; as a wedge's node, the cells around it are redone together,
            // cut along the curve through it (plan_wedges).
            if (through_node_diagonally(int(index))) {
                x.alive = false;
                nodes_passed_.insert(int(index));
                continue;
            }
            // Of `candidates` that `usable` admits, the nearest that q can go into without folding
            // its face, else the nearest; of those equally near (a node is as near to the two
            // segments beside a marching-tetrahedra vertex), the one whose ends' normals differ
            // most: the surface turns across it, so the feature edge cut there leaves each
            // polygon on one face of the solid. Then the segments' vertices decide.
            auto choose = [&](const auto& usable) -> const Candidate* {
                double near_any = std::numeric_limits<double>::infinity(), near_flat = near_any;
                for (const Candidate& c : candidates)
                    if (usable(c)) {
                        near_any = std::min(near_any, c.distance);
                        if (!c.folds) near_flat = std::min(near_flat, c.distance);
                    }
                const bool any_flat = near_flat <= h;
                const Candidate* best = nullptr;
                for (const Candidate& c : candidates) {
                    if (!usable(c) || !(any_flat ? !c.folds && c.distance <= near_flat + 1e-9 * h : c.distance <= near_any + 1e-9 * h))
                        continue;
                    if (!best || std::tie(c.bend, c.segment) < std::tie(best->bend, best->segment)) best = &c;
                }
                return best;
            };
            if (const Candidate* best = choose([](const Candidate&) { return true; }))
                x.segment = best->segment, x.face = best->face;
            if (candidates.empty() || nearest > h) {
                x.alive = false;
                continue;
            }
            // A curve through a grid node from one cell to the one diagonally across it links
            // the node's crossing in two cells that share no face: one segment serves only one
            // of them, so the other gets the same vertex through a segment of its own (a clone),
            // and the cell between them takes it twice, its ring pinched there (build_cell).
            const auto chosen = cells_of_face(x.face);
            for (uint64_t cell : cells_around(q)) {
                if (cell == chosen[0] || cell == chosen[1]) continue;
                const int self = int(index);
                // Only a link across the cell, or a spoke from the cell's corner: one along a
                // grid edge through q (both ends on it) is joined by the cells around that edge
                // as they are.
                auto across = [&](const Vec& other) {
                    int apart = 0;
                    for (int a = 0; a < 3; ++a) apart += other[a] != q[a];
                    return apart >= 2;
                };
                const auto links = links_.find(cell);
                const bool linked = links != links_.end() && std::any_of(links->second.begin(), links->second.end(), [&](const auto& l) {
                    return (l.first == self || l.second == self) &&
                           across(positions_[crossings_[l.first == self ? l.second : l.first].vertex]);
                });
                const auto apex = apex_.find(cell);
                if (!linked && !(apex != apex_.end() && across(positions_[apex->second]))) continue;
                const Candidate* best = choose([&](const Candidate& c) {
                    const auto two = cells_of_face(c.face);
                    return (two[0] == cell || two[1] == cell) && c.segment != x.segment && c.distance <= h;
                });
                if (!best) continue;
                auto clone = std::find_if(clones.begin(), clones.end(), [&](const Clone& k) { return k.of == self && k.segment == best->segment; });
                if (clone == clones.end()) clone = clones.insert(clones.end(), {self, best->face, best->segment, {}});
                clone->cells.push_back(cell);
            }
        }
        for (const Clone& k : clones) {
            Crossing clone = crossings_[k.of];
            clone.face = k.face;
            clone.segment = k.segment;
            const int id = int(crossings_.size());
            crossings_.push_back(clone);
            face_crossings_[k.face].push_back(id);
            for (uint64_t cell : k.cells)
                if (const auto links = links_.find(cell); links != links_.end())
                    for (auto& link : links->second) {
                        if (link.first == k.of) link.first = id;
                        if (link.second == k.of) link.second = id;
                    }
        }
    }

    /// Whether crossing x is a grid node the curve passes from one cell into the one across
    /// it in all three axes (the two share only the node). Not where it touches grid planes
    /// at the node (the Steinmetz curve at (0, 1, 1)): tried too, such nodes came out exact
    /// on a segment and were lost as wedges on some lattices ([-1.5, 1.5]³ at 13 nodes).
    bool through_node_diagonally(int x) const {
        const Vec& q = positions_[crossings_[x].vertex];
        for (int a = 0; a < 3; ++a)
            if (plane_of(q, a) < 0) return false;
        const auto partners = partners_.find(x);
        if (partners == partners_.end()) return false;
        for (int p : partners->second)
            for (int r : partners->second) {
                const Vec &u = positions_[crossings_[p].vertex], &v = positions_[crossings_[r].vertex];
                bool opposite = true;
                for (int a = 0; a < 3; ++a) opposite &= (u[a] - q[a]) * (v[a] - q[a]) < 0;
                if (opposite) return true;
            }
        return false;
    }

    /// The boundary loop of a patch that is a disc, its inner vertices inside the cell.
    bool boundary_loop(const std::vector<uint32_t>& patch, const Cell& cell, std::vector<uint32_t>& loop) const {
        std::vector<std::vector<uint32_t>> rings;
        long euler = 0;
        if (!boundary_rings(patch, cell, rings, euler) || rings.size() != 1 || euler != 1) return false;
        loop = std::move(rings.front());
        return true;
    }

    /// The boundary loops of a patch whose edges are each in one triangle or two (oriented
    /// alike) and whose boundary does not touch itself, each loop going the way its triangles
    /// do, from its least vertex; `euler` the patch's V − E + F (1: a disc, 0 with two loops: an
    /// annulus). False also when a vertex off the boundary lies outside the cell.
    bool boundary_rings(const std::vector<uint32_t>& patch, const Cell& cell, std::vector<std::vector<uint32_t>>& rings,
                        long& euler) const {
        std::vector<Tri> triangles;
        triangles.reserve(patch.size());
        for (uint32_t t : patch) triangles.push_back(mesh_.triangles[t]);
        return boundary_rings(triangles, &cell, rings, euler);
    }

    /// The same for triangles given as such; with no `cell`, inner vertices may lie anywhere.
    bool boundary_rings(const std::vector<Tri>& patch, const Cell* cell, std::vector<std::vector<uint32_t>>& rings,
                        long& euler) const {
        // Sorted vectors, not maps: a band's patch has thousands of triangles (Tor1 at 128 nodes).
        using Edge = std::pair<uint32_t, uint32_t>;
        std::vector<Edge> directed;
        directed.reserve(patch.size() * 3);
        for (const Tri& t : patch)
            for (int k = 0; k < 3; ++k) directed.push_back({t[k], t[(k + 1) % 3]});
        std::sort(directed.begin(), directed.end());
        if (std::adjacent_find(directed.begin(), directed.end()) != directed.end()) return false;  // twice one way
        std::vector<Edge> next;  // the boundary edges, by their first vertex
        std::size_t undirected = 0, vertices = 0;
        for (std::size_t i = 0; i < directed.size(); ++i) {
            const Edge& e = directed[i];
            vertices += i == 0 || directed[i - 1].first != e.first;  // each vertex starts an edge of its triangles
            if (std::binary_search(directed.begin(), directed.end(), Edge{e.second, e.first})) {
                undirected += e.first < e.second;
                continue;
            }
            ++undirected;
            if (!next.empty() && next.back().first == e.first) return false;  // the boundary touches itself
            next.push_back(e);
        }
        if (next.empty()) return false;
        euler = long(vertices) - long(undirected) + long(patch.size());
        auto after = [&](uint32_t v) {  // v's place in `next`, or next.size()
            const auto it = std::lower_bound(next.begin(), next.end(), Edge{v, 0});
            return it != next.end() && it->first == v ? std::size_t(it - next.begin()) : next.size();
        };
        std::vector<char> placed(next.size(), 0);
        rings.clear();
        for (std::size_t first = 0; first < next.size(); ++first) {
            if (placed[first]) continue;
            placed[first] = 1;
            std::vector<uint32_t> ring{next[first].first};
            for (std::size_t at = first;;) {
                const uint32_t to = next[at].second;
                if (to == ring.front()) break;
                at = after(to);
                if (at == next.size() || placed[at]) return false;
                placed[at] = 1;
                ring.push_back(to);
            }
            rings.push_back(std::move(ring));
        }
        for (std::size_t i = 0; cell && i < directed.size(); ++i)
            if ((i == 0 || directed[i - 1].first != directed[i].first) && after(directed[i].first) == next.size() &&
                !cell->contains(positions_[directed[i].first], -1e-9 * cell->h))
                return false;
        return true;
    }

    /// The polygon `poly` (a closed loop of vertex indices) cut into triangles of least total
    /// area, with no triangle edge across one of the cell's faces (it would lie in the plane
    /// the neighbour's patch meets) and none degenerate; then checked to be a graph over the
    /// plane across its mean normal (its triangles keep their orientation there and its
    /// boundary does not cross itself), so it cannot fold or cross itself.
    bool triangulate(const std::vector<uint32_t>& poly, const Cell& cell, std::vector<Tri>& out, int max_vertices = 64,
                     const std::function<bool(uint32_t, uint32_t)>& allowed = {}) const {
        const int n = int(poly.size());
        if (n < 3 || n > max_vertices) return false;
        const double h = cell.h, tolerance = 1e-9 * h;
        std::vector<int> faces(n);
        for (int i = 0; i < n; ++i) faces[i] = cell.faces_of(positions_[poly[i]], tolerance);
        auto diagonal_ok = [&](int i, int j) { return (faces[i] & faces[j]) == 0 && (!allowed || allowed(poly[i], poly[j])); };
        const double inf = std::numeric_limits<double>::infinity();
        std::vector<double> cost(n * n, 0);
        std::vector<int> best(n * n, -1);
        for (int length = 2; length < n; ++length)
            for (int i = 0; i + length < n; ++i) {
                const int j = i + length;
                double c = inf;
                if (!(i == 0 && j == n - 1) && !diagonal_ok(i, j)) {
                    cost[i * n + j] = inf;
                    continue;
                }
                for (int k = i + 1; k < j; ++k) {
                    const double sides = cost[i * n + k] + cost[k * n + j];
                    const Vec normal = cross(sub(positions_[poly[k]], positions_[poly[i]]),
                                             sub(positions_[poly[j]], positions_[poly[i]]));
                    const double area = norm(normal) / 2;
                    if (!(area >= kMinChainArea * h * h) || !(sides + area < c)) continue;
                    c = sides + area;
                    best[i * n + j] = k;
                }
                cost[i * n + j] = c;
            }
        if (!(cost[n - 1] < inf)) return false;
        std::vector<Tri> triangles;
        std::vector<std::pair<int, int>> stack{{0, n - 1}};
        while (!stack.empty()) {
            const auto [i, j] = stack.back();
            stack.pop_back();
            if (j - i < 2) continue;
            const int k = best[i * n + j];
            triangles.push_back({poly[i], poly[k], poly[j]});
            stack.push_back({i, k});
            stack.push_back({k, j});
        }
        // The mean normal (Newell's), and the plane across it.
        Vec normal{0, 0, 0};
        for (int i = 0; i < n; ++i) {
            const Vec c = cross(positions_[poly[i]], positions_[poly[(i + 1) % n]]);
            for (int a = 0; a < 3; ++a) normal[a] += c[a];
        }
        const double length = norm(normal);
        if (!(length > 0)) return false;
        for (double& c : normal) c /= length;
        for (const Tri& t : triangles)
            if (!(dot(area_normal(t), normal) / 2 >= kMinChainProjectedArea * h * h) || !triangle_near_surface(t, h)) return false;
        if (!loops_simple({poly}, normal, h)) return false;
        out.insert(out.end(), triangles.begin(), triangles.end());
        return true;
    }

    /// Triangle t's normal, its length twice the area.
    Vec area_normal(const Tri& t) const {
        return cross(sub(positions_[t[1]], positions_[t[0]]), sub(positions_[t[2]], positions_[t[0]]));
    }

    /// Whether closed loops of vertices, projected across the unit vector `normal`, are simple
    /// and apart: no two of their segments cross, but neighbours on one loop.
    bool loops_simple(const std::vector<std::vector<uint32_t>>& loops, const Vec& normal, double h) const {
        std::vector<uint32_t> points;
        std::vector<std::pair<std::size_t, std::size_t>> segments;
        for (const auto& loop : loops) {
            const std::size_t first = points.size();
            points.insert(points.end(), loop.begin(), loop.end());
            for (std::size_t k = 0; k < loop.size(); ++k) segments.push_back({first + k, first + (k + 1) % loop.size()});
        }
        const std::vector<std::array<double, 2>> flat = projected(points, normal);
        for (std::size_t a = 0; a < segments.size(); ++a)
            for (std::size_t b = a + 1; b < segments.size(); ++b) {
                const auto [a0, a1] = segments[a];
                const auto [b0, b1] = segments[b];
                if (a1 == b0 || b1 == a0) continue;  // neighbours on one loop
                if (segments_cross_2d(flat[a0], flat[a1], flat[b0], flat[b1], 1e-12 * h * h)) return false;
            }
        return true;
    }

    /// Whether p is within `bound` of the surface, to first order (|f| / |∇f|).
    bool near_surface(const Vec& p, double bound) const {
        field_.at(p);
        const double slope = norm(field_.gradient(0));
        return std::fabs(field_.value(0)) <= bound * slope;
    }

    Vec centroid(const Tri& t) const {
        Vec c{};
        for (int a = 0; a < 3; ++a) c[a] = (positions_[t[0]][a] + positions_[t[1]][a] + positions_[t[2]][a]) / 3;
        return c;
    }

    /// Whether triangle t is within kMaxCentroidDistance cells of the surface at its centroid
    /// and, if an edge is longer than two cells (a triangle no one cell holds), within
    /// kMaxBandDistance along its normal at its edges' midpoints and halfway from the centroid
    /// to each vertex: a triangle cells long bridges a face that curves under it (Tor1 at 65
    /// nodes: a fan four cells long over its twisted tube, 0.54 cells from the surface in its
    /// middle, its centroid within the bound). Along the normal, by the field's sign, not to
    /// first order: |f| / |∇f| is three times the distance inside an acute R0 wedge, whose
    /// chamfers (the FLOZ3 plate's 39° edge) are within the bound.
    bool triangle_near_surface(const Tri& t, double h) const {
        const Vec c = centroid(t);
        if (!near_surface(c, kMaxCentroidDistance * h)) return false;
        const Vec &p = positions_[t[0]], &q = positions_[t[1]], &r = positions_[t[2]];
        if (std::max({norm(sub(p, q)), norm(sub(q, r)), norm(sub(r, p))}) <= 2 * h) return true;
        Vec normal = area_normal(t);
        const double length = norm(normal);
        if (!(length > 0)) return false;
        for (double& x : normal) x /= length;
        for (const Vec& x : {midpoint(p, q), midpoint(q, r), midpoint(r, p), midpoint(c, p), midpoint(c, q), midpoint(c, r)})
            if (!surface_along(x, normal, kMaxBandDistance * h)) return false;
        return true;
    }

    /// Whether the surface is within `reach` of p along the unit vector n: the field's sign
    /// differs among p − reach·n, p and p + reach·n, or p is on it (zero, as on an edge where
    /// the gradient is NaN, or within round-off to first order).
    bool surface_along(const Vec& p, const Vec& n, double reach) const {
        auto value = [&](double s) {
            field_.at(Vec{p[0] + s * n[0], p[1] + s * n[1], p[2] + s * n[2]});
            return field_.value(0);
        };
        const double below = value(-reach), above = value(reach), at = value(0);
        if ((below > 0) != (above > 0) || (at > 0) != (above > 0) || at == 0) return true;
        return std::fabs(at) <= 1e-9 * reach * norm(field_.gradient(0));
    }

    /// The vertices projected onto the plane across the unit vector `normal`.
    std::vector<std::array<double, 2>> projected(const std::vector<uint32_t>& vertices, const Vec& normal) const {
        const Vec helper = std::fabs(normal[0]) < 0.6 ? Vec{1, 0, 0} : Vec{0, 1, 0};
        Vec e1 = cross(normal, helper);
        const double l1 = norm(e1);
        for (double& c : e1) c /= l1;
        const Vec e2 = cross(normal, e1);
        std::vector<std::array<double, 2>> flat(vertices.size());
        for (std::size_t i = 0; i < vertices.size(); ++i) flat[i] = {dot(positions_[vertices[i]], e1), dot(positions_[vertices[i]], e2)};
        return flat;
    }

    // ---- Wedges: features in cells with no triangles --------------------------------------

    Vec node_position(int node) const {
        return positions_[node >= 0 ? crossings_[node].vertex : tips_[std::size_t(-1 - node)]];
    }
    uint32_t node_vertex(int node) const { return node >= 0 ? crossings_[node].vertex : tips_[std::size_t(-1 - node)]; }

    /// The tree's neighbours of a node: a crossing's linked crossings and the tip whose cell
    /// holds it; a tip's crossings on its cells' faces (the ends of the edges into it).
    std::vector<int> node_neighbours(int node) const {
        std::vector<int> out;
        if (node >= 0) {
            if (const auto it = partners_.find(node); it != partners_.end()) out = it->second;
            if (const auto it = tip_crossings_.find(node); it != tip_crossings_.end()) out.push_back(it->second);
        } else if (const auto it = crossings_of_tip_.find(node); it != crossings_of_tip_.end()) {
            out = it->second;
        }
        for (int& m : out)  // a crossing at the tip itself is the tip
            if (const auto it = tip_at_.find(m); it != tip_at_.end()) m = it->second;
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        std::erase(out, node);
        return out;
    }

    /// Whether the link between crossings a and b, near corner p (within two cell diagonals,
    /// in a cell touching one of p's `corner_cells`), turns at p: seen from p its ends lie 20°
    /// to 160° apart, where two pieces of one smooth curve through p lie 180° apart and two of
    /// one side 0° apart.
    bool cuts_kink(const Vec& p, const std::vector<uint64_t>& corner_cells, int a, int b) const {
        const double reach = 2 * norm(Vec{step_[0], step_[1], step_[2]});
        const Vec u = sub(positions_[crossings_[a].vertex], p), v = sub(positions_[crossings_[b].vertex], p);
        const double nu = norm(u), nv = norm(v);
        if (nu > reach || nv > reach || nu <= 1e-9 * lattice_h() || nv <= 1e-9 * lattice_h()) return false;
        const double cosine = dot(u, v) / (nu * nv);
        if (cosine > std::cos(std::numbers::pi / 9) || cosine < std::cos(8 * std::numbers::pi / 9)) return false;
        for (uint64_t id : cells_holding(positions_[crossings_[a].vertex], positions_[crossings_[b].vertex]))
            for (uint64_t corner : corner_cells)
                if (touching(id, corner)) return true;
        return false;
    }

    /// After choose_segments: the crossings that found no segment (and tips), grouped by their
    /// links into trees; each tree with links to crossings on patches becomes a wedge.
    void plan_wedges(const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of) {
        const double h = lattice_h();
        std::vector<int> nodes;
        for (std::size_t t = 0; t < tips_.size(); ++t) nodes.push_back(-1 - int(t));
        std::vector<char> corner_vertex(positions_.size(), 0);
        for (const auto& [id, apex] : apex_) corner_vertex[apex] = 1;
        for (uint32_t tip : tips_) corner_vertex[tip] = 1;
        std::vector<Vec> corners;
        for (std::size_t v = 0; v < positions_.size(); ++v)
            if (corner_vertex[v]) corners.push_back(positions_[v]);
        for (std::size_t x = 0; x < crossings_.size(); ++x) {
            // A cap's rim in cells with no triangles is where the surface meets the cap at a
            // shallow angle; its blocks, long and refused, cost more than all the rest (they
            // took 19 times the mesh on the tanglecube cut by [-1, 1]³ at 257 nodes), so it
            // stays cut.
            if (crossings_[x].alive || is_cap_[std::size_t(crossings_[x].operation)]) continue;
            bool at_corner = false;  // a crossing a corner replaced
            for (const Vec& c : corners) at_corner |= norm(sub(c, positions_[crossings_[x].vertex])) <= 1e-9 * h;
            if (!at_corner) nodes.push_back(int(x));
        }
        if (nodes.empty()) return;
        // The edges into a tip: the chains of its operations that end (one link) near it. A
        // trace stops at the last face before the curve leaves the surface, in the tip's cell
        // or the one before it.
        for (std::size_t t = 0; t < tips_.size(); ++t) {
            const int tip = -1 - int(t);
            const Vec& p = positions_[tips_[t]];
            field_.at(p);
            std::vector<char> through(field_.operations().size(), 0);
            for (std::size_t k = 0; k < through.size(); ++k)
                through[k] = vanishes(field_, field_.operations()[k].a, h) && vanishes(field_, field_.operations()[k].b, h);
            // A chain that passes the tip (the trace crossed the kink there) is cut at it: the
            // link through its cell becomes two edges into the tip.
            const std::vector<uint64_t> tip_cells = cells_around(p);
            for (std::size_t x = 0; x < crossings_.size(); ++x) {
                if (crossings_[x].alive || !through[std::size_t(crossings_[x].operation)]) continue;
                auto& list = partners_[int(x)];
                for (std::size_t i = 0; i < list.size();) {
                    const int y = list[i];
                    bool passes = false;
                    const std::vector<uint64_t> near = cells_around(positions_[crossings_[x].vertex]),
                                                far = cells_around(positions_[crossings_[y].vertex]);
                    for (uint64_t id : tip_cells)
                        passes |= std::find(near.begin(), near.end(), id) != near.end() &&
                                  std::find(far.begin(), far.end(), id) != far.end();
                    if (!passes || crossings_[y].alive) {
                        ++i;
                        continue;
                    }
                    list.erase(list.begin() + long(i));
                    std::erase(partners_[y], int(x));
                    tip_crossings_[int(x)] = tip, tip_crossings_[y] = tip;
                }
            }
            // So is a link between crossings on patches that cuts the kink in a cell beside the
            // tip's: the plate at 27 nodes, its corner (-0.85, 1, -1.15) 0.0017 above a grid
            // plane, where the trace went from the vertical edge to the slab edge below the
            // corner. Its ends then become edges into the tip.
            for (std::size_t x = 0; x < crossings_.size(); ++x) {
                if (!crossings_[x].alive || !through[std::size_t(crossings_[x].operation)]) continue;
                const std::vector<int> partners = partners_[int(x)];
                for (int y : partners)
                    if (y > int(x) && crossings_[y].alive && crossings_[y].operation == crossings_[x].operation &&
                        cuts_kink(p, tip_cells, int(x), y))
                        drop_link(int(x), y);
            }
            for (std::size_t x = 0; x < crossings_.size(); ++x) {
                const double distance = norm(sub(positions_[crossings_[x].vertex], p));
                if (distance <= 1e-9 * h) {
                    tip_at_[int(x)] = tip;
                    continue;
                }
                const auto partners = partners_.find(int(x));
                if (distance > 2 * norm(Vec{step_[0], step_[1], step_[2]}) ||
                    !through[std::size_t(crossings_[x].operation)] ||
                    (partners != partners_.end() && partners->second.size() > 1))
                    continue;
                if (const auto it = tip_crossings_.find(int(x));
                    it != tip_crossings_.end() && norm(sub(positions_[tips_[std::size_t(-1 - it->second)]],
                                                            positions_[crossings_[x].vertex])) <= distance)
                    continue;  // nearer another tip
                bool nearer_corner = false;  // the chain's end at another corner (a short edge between two)
                for (const Vec& c : corners)
                    nearer_corner |= norm(sub(c, p)) > 1e-9 * h && norm(sub(c, positions_[crossings_[x].vertex])) < distance;
                if (nearer_corner) continue;
                tip_crossings_[int(x)] = tip;
            }
        }
        for (const auto& [x, tip] : tip_crossings_) crossings_of_tip_[tip].push_back(x);
        // Trees: the nodes joined by links.
        Pieces trees_of;
        for (int n : nodes) trees_of.add(n);
        for (int n : nodes)
            for (int m : node_neighbours(n)) {
                if (trees_of.has(m)) {
                    trees_of.join(n, m);
                } else if (const auto partners = partners_.find(m); n < 0 && partners != partners_.end()) {
                    // A tip's edge ends on a patch beside the tip and goes on into a gap (the
                    // plate's edge from (-0.85, 1, -1.15) at 61 nodes): one tree, else the
                    // gap's block would ring the tip's cell.
                    for (int k : partners->second)
                        if (trees_of.has(k)) trees_of.join(n, k);
                }
            }
        std::map<int, Wedge> trees;
        for (int n : nodes) trees[trees_of.root(n)].nodes.push_back(n);
        // Closed creases: trees with no tip whose crossings, with the live ones between them,
        // go round one loop (a concave crease through cells with every node inside).
        std::vector<Wedge> bands;
        std::set<int> in_band;
        for (const auto& [r, wedge] : trees) {
            if (in_band.count(r) || std::any_of(wedge.nodes.begin(), wedge.nodes.end(), [](int n) { return n < 0; }))
                continue;
            Wedge band;
            band.cycle = closed_crease(wedge.nodes.front());
            for (int x : band.cycle)
                if (trees_of.has(x)) in_band.insert(trees_of.root(x)), band.nodes.push_back(x);
            if (!band.cycle.empty()) bands.push_back(std::move(band));
        }
        std::vector<Wedge> planned;
        for (auto& [r, wedge] : trees) {
            for (int a = 0; a < 3; ++a) wedge.span[a] = {cells_[a], -1};
            auto widen = [&](uint64_t id) {
                const auto c = coords(id);
                for (int a = 0; a < 3; ++a)
                    wedge.span[a] = {std::min(wedge.span[a].first, long(c[a])), std::max(wedge.span[a].second, long(c[a]))};
            };
            for (int n : wedge.nodes) {
                const std::vector<uint64_t> around = cells_around(node_position(n));
                for (uint64_t id : around) widen(id);
                if (n < 0) {  // a tip's edges onto the patches beside its cell
                    for (int m : node_neighbours(n)) {
                        if (m < 0 || !crossings_[m].alive) continue;
                        for (uint64_t id : cells_around(positions_[crossings_[m].vertex]))
                            if ((!has_patch_ || has_patch_(id)) &&
                                std::any_of(around.begin(), around.end(), [&](uint64_t c) { return touching(id, c); }))
                                wedge.seeds.push_back(id);
                    }
                    continue;
                }
                for (int m : node_neighbours(n)) {
                    if (m < 0 || !crossings_[m].alive) continue;
                    for (uint64_t id : cells_around(positions_[crossings_[m].vertex]))
                        if (has_patch_ && has_patch_(id)) {
                            const auto near = cells_around(positions_[crossings_[n].vertex]);
                            if (std::find(near.begin(), near.end(), id) != near.end()) wedge.seeds.push_back(id), widen(id);
                        }
                }
            }
            if (wedge.seeds.empty()) continue;
            if (std::all_of(wedge.nodes.begin(), wedge.nodes.end(), [&](int n) { return nodes_passed_.count(n) > 0; })) {
                wedge.around_nodes = true;
                wedge.radius = -1;
            }
            planned.push_back(std::move(wedge));
        }
        // Trees that reach a tip take their cells first, larger blocks included (a tip has no
        // other way onto the mesh); the gaps in the middle of an edge wait until they are built.
        for (Wedge& wedge : planned) {
            if (std::none_of(wedge.nodes.begin(), wedge.nodes.end(), [](int n) { return n < 0; })) {
                mid_edge_wedges_.push_back(std::move(wedge));
                continue;
            }
            wedges_.push_back(std::move(wedge));
            group_wedge(wedges_.size() - 1);
        }
        // Each band is redone now, before the crease's cells are one by one (a cell that fails
        // there is fanned from a point of the crease and would leave a hole in the band); its
        // cells are then done. If it cannot be, nothing has changed: its trees stay planned.
        for (Wedge& band : bands) {
            plan_band(band);
            wedges_.push_back(std::move(band));
            const std::size_t w = wedges_.size() - 1;
            while (group_wedge(w)) {
                const std::vector<uint64_t> cells = wedges_[w].cells;
                std::vector<uint32_t> joined;
                for (uint64_t g : cells)
                    if (const auto patch = patch_of(g)) joined.insert(joined.end(), patch->begin(), patch->end());
                std::vector<Tri> triangles;
                if (build_band(wedges_[w], joined, patch_of, triangles)) {
                    results_[cells.front()] = {std::move(joined), std::move(triangles)};
                    banded_.insert(cells.begin(), cells.end());
                    const std::set<int> nodes(wedges_[w].nodes.begin(), wedges_[w].nodes.end());
                    std::erase_if(mid_edge_wedges_, [&](const Wedge& tree) { return nodes.count(tree.nodes.front()) > 0; });
                    break;
                }
                for (uint64_t g : cells) wedge_of_.erase(g);
                wedges_[w].cells.clear();
            }
        }
    }

    /// The crossings of the closed crease through crossing `start`, in order round it: every
    /// crossing linked to two others of the same operation, none at a tip or a grid node the
    /// curve passes diagonally; empty if the links do not close into such a loop.
    std::vector<int> closed_crease(int start) const {
        std::vector<int> cycle{start};
        for (int x = start, before = -1;;) {
            const auto it = partners_.find(x);
            if (it == partners_.end() || it->second.size() != 2 || tip_crossings_.count(x) || tip_at_.count(x) ||
                nodes_passed_.count(x) || crossings_[x].operation != crossings_[start].operation)
                return {};
            const int next = it->second[0] != before ? it->second[0] : it->second[1];
            if (next == start) break;
            if (cycle.size() >= crossings_.size()) return {};
            before = x, x = next;
            cycle.push_back(x);
        }
        return cycle.size() >= 3 ? cycle : std::vector<int>{};
    }

    /// The cells within `radius` (in every axis) of the cells crease crossings lie in.
    std::set<uint64_t> tube_around(const std::vector<int>& cycle, int radius) const {
        std::set<uint64_t> near, tube;
        for (int x : cycle)
            for (uint64_t id : cells_around(positions_[crossings_[x].vertex])) near.insert(id);
        for (uint64_t id : near) {
            const auto c = coords(id);
            for (long dz = -radius; dz <= radius; ++dz)
                for (long dy = -radius; dy <= radius; ++dy)
                    for (long dx = -radius; dx <= radius; ++dx) {
                        const long k[3] = {long(c[0]) + dx, long(c[1]) + dy, long(c[2]) + dz};
                        if (k[0] >= 0 && k[1] >= 0 && k[2] >= 0 && k[0] < cells_[0] && k[1] < cells_[1] && k[2] < cells_[2])
                            tube.insert(cell_id(uint64_t(k[0]), uint64_t(k[1]), uint64_t(k[2])));
                    }
        }
        return tube;
    }

    /// A band's seeds: the cells with triangles touching those its crossings lie in, so a
    /// crease whose crossings all died still reaches the patches over it.
    void plan_band(Wedge& band) const {
        for (uint64_t id : tube_around(band.cycle, 1))
            if (!has_patch_ || has_patch_(id)) band.seeds.push_back(id);
    }

    /// Joins the cells with triangles of band w's next wider tube round its crease (one cell,
    /// then two), reached from its seeds across faces: a block that follows the crease, not
    /// the box around it (round a pawn's neck that box holds patches cells away from it).
    bool group_band(std::size_t w) {
        Wedge& band = wedges_[w];
        band.cells.clear();
        // The cells holding another edge's crossing or link and none of this crease's stay out
        // (the band would lose it; the pawn's spire-collar crease at 24 nodes has the
        // head-collar one's a cell away): they are built after the band, so its strips may
        // not enter them (loft_band). One holding both stays in, and the band is refused.
        const std::set<int> on_crease(band.cycle.begin(), band.cycle.end());
        while (++band.radius <= kMaxBandRadius) {
            std::set<uint64_t> tube = tube_around(band.cycle, band.radius);
            band.left_out.clear();
            for (uint64_t id : tube)
                if (const auto [own, other] = crease_holdings(id, on_crease); other && !own) band.left_out.push_back(id);
            for (uint64_t id : band.left_out) tube.erase(id);
            if (std::any_of(tube.begin(), tube.end(), [&](uint64_t id) { return frozen(id); })) return false;
            std::vector<uint64_t> reached = reach_cells(band.seeds, [&](uint64_t id) { return tube.count(id) > 0; });
            if (reached.empty()) continue;
            band.tube.assign(tube.begin(), tube.end());
            band.block = joined_box(band.tube);
            band.cells = std::move(reached);
            for (uint64_t id : band.cells) wedge_of_[id] = w;
            return true;
        }
        return false;
    }

    /// Joins the cells with triangles of wedge w's next larger block (one cell around the
    /// tree's cells, then two, up to kMaxWedgeRadius; for a wedge around nodes only the tree's
    /// cells) reached from its seeds across faces, so the joined patches are one piece of
    /// surface; false when none is left to try.
    bool group_wedge(std::size_t w) {
        auto frozen_in = [&](const std::array<std::pair<long, long>, 3>& range) {
            for (uint64_t id : frozen_) {
                const auto c = coords(id);
                bool in = true;
                for (int a = 0; a < 3; ++a) in = in && long(c[a]) >= range[a].first && long(c[a]) <= range[a].second;
                if (in) return true;
            }
            return false;
        };
        Wedge& wedge = wedges_[w];
        if (!wedge.cycle.empty()) return group_band(w);
        wedge.cells.clear();
        while (++wedge.radius <= (wedge.around_nodes ? 0 : kMaxWedgeRadius)) {
            std::array<std::pair<long, long>, 3> range;
            for (int a = 0; a < 3; ++a) {
                range[a] = {std::max(0L, wedge.span[a].first - wedge.radius),
                            std::min(long(cells_[a]) - 1, wedge.span[a].second + wedge.radius)};
                wedge.block.lo[a] = min_[a] + double(range[a].first) * step_[a];
                wedge.block.hi[a] = min_[a] + double(range[a].second + 1) * step_[a];
            }
            wedge.block.h = lattice_h();
            if (frozen_in(range)) return false;  // a larger block would hold it too
            std::vector<uint64_t> reached = reach_cells(wedge.seeds, [&](uint64_t id) {
                const auto c = coords(id);
                for (int a = 0; a < 3; ++a)
                    if (long(c[a]) < range[a].first || long(c[a]) > range[a].second) return false;
                return true;
            });
            if (reached.empty()) continue;
            wedge.cells = std::move(reached);
            for (uint64_t id : wedge.cells) wedge_of_[id] = w;
            return true;
        }
        return false;
    }

    /// The cells with triangles in a block (`in_block`), not a corner's, a group's or another
    /// wedge's, reached from `seeds` across faces among them, sorted: the joined patches are
    /// one piece of surface.
    std::vector<uint64_t> reach_cells(const std::vector<uint64_t>& seeds, const std::function<bool(uint64_t)>& in_block) const {
        auto eligible = [&](uint64_t id) {
            return in_block(id) && (!has_patch_ || has_patch_(id)) && !apex_.count(id) && !groups_.count(id) &&
                   !wedge_of_.count(id) && !frozen(id);
        };
        std::set<uint64_t> reached;
        std::vector<uint64_t> stack;
        for (uint64_t id : seeds)
            if (eligible(id) && reached.insert(id).second) stack.push_back(id);
        while (!stack.empty()) {
            const uint64_t id = stack.back();
            stack.pop_back();
            for (uint64_t next : face_neighbours(id))
                if (eligible(next) && reached.insert(next).second) stack.push_back(next);
        }
        return {reached.begin(), reached.end()};
    }

    /// Whether the graph on points `inner` and `leaves` with `edges` is one piece.
    static bool connected(const std::set<std::pair<int, int>>& edges, const std::set<int>& inner, const std::set<int>& leaves) {
        Pieces points;
        for (int x : inner) points.add(x);
        for (int x : leaves) points.add(x);
        std::size_t pieces = points.parent.size();
        for (const auto& [a, b] : edges) pieces -= points.join(a, b);
        return pieces == 1;
    }

    /// A piece of a wedge's links with one loop in it: the edges round a face of the solid all
    /// in cells with no triangles, or in the joined ones (the FLOZ3 plate's end face at 31
    /// nodes). The faces outside the loop reach it through the branches from the ring.
    struct PieceLoop {
        std::vector<int> order;              ///< the loop's points, going round it
        std::map<int, std::size_t> at;       ///< a point on the loop → its place in `order`
        std::map<int, int> toward;           ///< a point off the loop → the next one toward it
        std::set<std::size_t> attached;      ///< the places where branches to the ring join

        /// The points from `target` to `goal` (two leaves next to each other on the ring among
        /// the piece's), both left out: down target's branch, along the arc of the loop with no
        /// other branch joining it, up goal's branch. False where that arc is not the only one
        /// (branches join the loop at two places or fewer).
        bool path(int target, int goal, std::vector<int>& out) const {
            auto branch = [&](int x) {  // x up to its place on the loop
                std::vector<int> chain{x};
                while (!at.count(chain.back())) chain.push_back(toward.at(chain.back()));
                return chain;
            };
            std::vector<int> from = branch(target), to = branch(goal);
            const std::size_t n = order.size(), start = at.at(from.back()), end = at.at(to.back());
            if (start == end) {  // the same place: where the branches meet, not round the loop
                if (attached.size() < 2) return false;
                while (from.size() > 1 && to.size() > 1 && from[from.size() - 2] == to[to.size() - 2])
                    from.pop_back(), to.pop_back();
                if (from.size() < 2 || to.size() < 2) return false;  // one leaf on the other's branch
                out.assign(from.begin() + 1, from.end());
                out.insert(out.end(), to.rbegin() + 1, to.rend() - 1);
                return true;
            }
            auto free_arc = [&](std::size_t step) {  // step n - 1 goes backwards
                for (std::size_t i = (start + step) % n; i != end; i = (i + step) % n)
                    if (attached.count(i)) return false;
                return true;
            };
            const bool forwards = free_arc(1), backwards = free_arc(n - 1);
            if (forwards == backwards) return false;
            const std::size_t step = forwards ? 1 : n - 1;
            out.assign(from.begin() + 1, from.end());
            for (std::size_t i = (start + step) % n;; i = (i + step) % n) {
                out.push_back(order[i]);
                if (i == end) break;
            }
            out.insert(out.end(), to.rbegin() + 1, to.rend() - 1);
            return true;
        }
    };

    /// Fills `loop` for piece p of the links (`adjacent`, `piece`): its loop, found by taking
    /// off the points with one link until none is left, and the branches to it; false if a
    /// leaf on the ring is on the loop.
    static bool find_loop(int p, const std::map<int, int>& piece, const std::map<int, std::vector<int>>& adjacent,
                          const std::set<int>& leaves, PieceLoop& loop) {
        std::map<int, std::size_t> degree;
        for (const auto& [x, q] : piece)
            if (q == p) degree[x] = adjacent.at(x).size();
        std::vector<int> ends;
        for (const auto& [x, d] : degree)
            if (d == 1) ends.push_back(x);
        std::set<int> off;
        while (!ends.empty()) {
            const int x = ends.back();
            ends.pop_back();
            off.insert(x);
            for (int y : adjacent.at(x))
                if (!off.count(y) && --degree[y] == 1) ends.push_back(y);
        }
        int first = INT_MIN;
        for (const auto& [x, d] : degree)
            if (!off.count(x)) {
                if (leaves.count(x)) return false;
                if (first == INT_MIN) first = x;
            }
        if (first == INT_MIN) return false;
        for (int x = first, before = INT_MIN;;) {
            loop.at[x] = loop.order.size();
            loop.order.push_back(x);
            int next = INT_MIN;
            for (int y : adjacent.at(x))
                if (!off.count(y) && y != before && !loop.at.count(y)) next = y;
            if (next == INT_MIN) break;
            before = x, x = next;
        }
        std::vector<int> todo(loop.order);
        while (!todo.empty()) {
            const int x = todo.back();
            todo.pop_back();
            for (int y : adjacent.at(x))
                if (off.count(y) && !loop.toward.count(y)) loop.toward[y] = x, todo.push_back(y);
        }
        for (int x : leaves)
            if (piece.count(x) && piece.at(x) == p) {
                int y = x;
                while (!loop.at.count(y)) y = loop.toward.at(y);
                loop.attached.insert(loop.at[y]);
            }
        return loop.order.size() >= 3;
    }

    /// The wedge's joined patch redone: its boundary ring with the crossings on it put in,
    /// cut by the tree (the polygon between two leaves next to each other on the ring is the
    /// ring's arc between them and the tree's path back), each polygon triangulated with
    /// least area and the polygons checked not to cross, as build_cell does for one cell.
    /// `disc`: whether the joined patch was one disc (else it may ring a corner's cell).
    bool build_wedge(const Wedge& wedge, const std::vector<uint32_t>& patch, std::vector<Tri>& out, bool& disc) {
        const Cell& box = wedge.block;
        const double h = box.h;
        std::vector<uint32_t> loop;
        disc = !patch.empty() && boundary_loop(patch, box, loop);
        if (!disc) return false;
        auto in_group = [&](uint64_t id) { return std::binary_search(wedge.cells.begin(), wedge.cells.end(), id); };
        // The crossings on the ring: alive, on a face between a joined cell and another.
        const std::size_t n = loop.size();
        std::set<int> on_ring;
        std::vector<int> on_faces;
        for (uint64_t id : wedge.cells)
            for (int x : crossings_in(id)) {
                if (on_ring.count(x)) continue;
                if (crossings_[x].on_mesh_vertex) {
                    if (std::find(loop.begin(), loop.end(), crossings_[x].vertex) != loop.end()) on_ring.insert(x);
                    continue;  // else inside: the tree may use it
                }
                const auto two = cells_of_face(crossings_[x].face);
                if (in_group(two[0]) && in_group(two[1])) continue;  // inside: the tree may use it
                on_faces.push_back(x);
                on_ring.insert(x);
            }
        std::vector<std::vector<int>> insert;
        if (!put_into_segments(loop, on_faces, h, insert)) return false;
        std::vector<uint32_t> ring;
        std::map<uint32_t, std::size_t> ring_index;  // vertex → its index in the ring
        for (std::size_t i = 0; i < n; ++i) {
            ring_index[loop[i]] = ring.size();
            ring.push_back(loop[i]);
            for (int x : insert[i]) {
                ring_index[crossings_[x].vertex] = ring.size();
                ring.push_back(crossings_[x].vertex);
            }
        }
        const std::size_t m = ring.size();
        // A live crossing off the ring lies inside the joined patch: on a face between two joined
        // cells, or a marching-tetrahedra vertex all of whose cells with triangles are joined.
        auto inside_joined = [&](int x) {
            if (!crossings_[x].on_mesh_vertex) {
                const auto two = cells_of_face(crossings_[x].face);
                return in_group(two[0]) && in_group(two[1]);
            }
            return patches_around_joined(positions_[crossings_[x].vertex], wedge.cells);
        };
        // The tree: from its nodes through the crossings inside the joined cells, up to the
        // crossings on the ring (its leaves).
        std::set<int> inner, leaves;
        std::set<std::pair<int, int>> edges;
        std::vector<int> stack;
        // A node inside the joined cells, or a leaf on the ring; false if neither (the chain
        // leaves the block elsewhere: it is too small).
        auto classify = [&](int b) {
            if (b < 0 || !crossings_[b].alive) {
                inner.insert(b), stack.push_back(b);
            } else if (on_ring.count(b)) {
                leaves.insert(b);
            } else {
                if (!inside_joined(b)) return false;
                inner.insert(b), stack.push_back(b);
            }
            return true;
        };
        // A link counts if it lies in a joined cell or in one with no triangles.
        auto inside = [&](int a, int b) {
            if (a < 0 || b < 0) return true;
            for (uint64_t id : cells_holding(positions_[crossings_[a].vertex], positions_[crossings_[b].vertex]))
                if (in_group(id) || (has_patch_ && !has_patch_(id))) return true;
            return false;
        };
        for (int a : wedge.nodes)
            if (!classify(a)) return false;
        stack.assign(wedge.nodes.begin(), wedge.nodes.end());
        while (!stack.empty()) {
            const int a = stack.back();
            stack.pop_back();
            for (int b : node_neighbours(a)) {
                if (!inside(a, b)) continue;
                edges.insert({std::min(a, b), std::max(a, b)});
                if (inner.count(b) || leaves.count(b)) continue;
                if (!classify(b)) return false;
            }
        }
        // One piece: a tree, or one loop with branches (a point left out would be lost).
        if (leaves.size() < 2 || edges.size() + 1 < inner.size() + leaves.size() || edges.size() > inner.size() + leaves.size() ||
            !connected(edges, inner, leaves))
            return false;
        // The other links in the joined cells (the edge going on from a leaf, another edge
        // passing) cut the joined patch too, as in one cell: with the tree they must make pieces
        // that are trees, each reaching the ring at two points or more, their other points on
        // faces between joined cells; else a link would be lost in the joined patch, and the
        // cells are left to themselves.
        for (uint64_t id : wedge.cells)
            if (const auto it = links_.find(id); it != links_.end())
                for (const auto& [a, b] : it->second) {
                    if (!crossings_[a].alive || !crossings_[b].alive || edges.count({a, b})) continue;
                    edges.insert({a, b});
                    for (int x : {a, b}) {
                        if (inner.count(x) || leaves.count(x)) continue;
                        if (on_ring.count(x)) leaves.insert(x);
                        else if (inside_joined(x)) inner.insert(x);
                        else return false;
                    }
                }
        std::map<int, int> piece;  // each point → its piece
        std::map<int, PieceLoop> loops;  // the pieces with a loop → it
        std::map<int, std::vector<int>> adjacent;
        for (const auto& [a, b] : edges) adjacent[a].push_back(b), adjacent[b].push_back(a);
        {
            int pieces = 0;
            for (const auto& [start, next] : adjacent) {
                if (piece.count(start)) continue;
                std::size_t points = 0, ends_on_ring = 0, degrees = 0;
                std::vector<int> todo{start};
                piece[start] = pieces;
                while (!todo.empty()) {
                    const int a = todo.back();
                    todo.pop_back();
                    ++points, ends_on_ring += leaves.count(a), degrees += adjacent[a].size();
                    for (int b : adjacent[a])
                        if (piece.emplace(b, pieces).second) todo.push_back(b);
                }
                if ((degrees != 2 * (points - 1) && degrees != 2 * points) || ends_on_ring < 2)
                    return false;  // not a tree (or one loop) reaching the ring twice
                if (degrees == 2 * points) loops[pieces];
                ++pieces;
            }
        }
        for (auto& [p, loop] : loops)
            if (!find_loop(p, piece, adjacent, leaves, loop)) return false;
        for (int x : inner)  // a branch ending inside would be on no face: that point lost
            if (adjacent[x].size() < 2) return false;
        for (int x : inner) {  // inside the block, and on no cell with triangles outside the group
            if (!box.contains(node_position(x), 1e-12 * h) || !patches_around_joined(node_position(x), wedge.cells))
                return false;
        }
        std::vector<std::pair<std::size_t, int>> ends;  // leaves by their place on the ring
        for (int x : leaves) {
            const auto it = ring_index.find(crossings_[x].vertex);
            if (it == ring_index.end()) return false;
            ends.push_back({it->second, x});
        }
        std::sort(ends.begin(), ends.end());
        // No new edge between two points of one cell with triangles outside the group: it could
        // be an edge that cell has too (on its faces, or across it).
        std::map<uint32_t, std::vector<uint64_t>> outside_cells;
        auto no_shared_outside_cell = [&](uint32_t u, uint32_t v) {
            for (uint32_t w : {u, v})
                if (!outside_cells.count(w)) {
                    auto& list = outside_cells[w];
                    for (uint64_t id : cells_around(positions_[w]))
                        if (!in_group(id) && (!has_patch_ || has_patch_(id))) list.push_back(id);
                }
            for (uint64_t id : outside_cells[u])
                if (std::find(outside_cells[v].begin(), outside_cells[v].end(), id) != outside_cells[v].end()) return false;
            return true;
        };
        for (const auto& [a, b] : edges)
            if (!no_shared_outside_cell(node_vertex(a), node_vertex(b))) return false;
        // The faces: from a leaf along the ring to the next leaf, then back through that leaf's
        // piece (the tree's path or the chord) to the leaf of the piece before it on the ring, and
        // on along the ring from there, until the face closes.
        std::map<int, int> previous;  // a leaf → the one before it on the ring among its piece's
        std::map<int, std::size_t> end_of;
        {
            std::map<int, std::vector<int>> by_piece;
            for (std::size_t e = 0; e < ends.size(); ++e) by_piece[piece[ends[e].second]].push_back(ends[e].second), end_of[ends[e].second] = e;
            for (const auto& [p, list] : by_piece)
                for (std::size_t i = 0; i < list.size(); ++i) previous[list[i]] = list[(i + list.size() - 1) % list.size()];
        }
        std::vector<std::vector<uint32_t>> polygons;
        std::vector<char> arc_done(ends.size(), 0);
        for (std::size_t first = 0; first < ends.size(); ++first) {
            if (arc_done[first]) continue;
            std::vector<uint32_t> poly;
            std::size_t e = first;
            while (!arc_done[e]) {
                arc_done[e] = 1;
                const auto [from, start] = ends[e];
                const auto [to, target] = ends[(e + 1) % ends.size()];
                for (std::size_t i = from;; i = (i + 1) % m) {
                    poly.push_back(ring[i]);
                    if (i == to) break;
                }
                // The piece's path from `target` back to `goal`, through inner nodes only.
                const int goal = previous[target];
                std::vector<int> between;
                if (const auto loop = loops.find(piece[target]); loop != loops.end()) {
                    if (!loop->second.path(target, goal, between)) return false;
                } else {
                    std::map<int, int> came_from{{target, target}};
                    std::vector<int> frontier{target};
                    while (!frontier.empty() && !came_from.count(goal)) {
                        const int a = frontier.back();
                        frontier.pop_back();
                        for (int b : adjacent[a])
                            if (!came_from.count(b) && (b == goal || inner.count(b))) came_from[b] = a, frontier.push_back(b);
                    }
                    if (!came_from.count(goal)) return false;
                    for (int a = came_from[goal]; a != target; a = came_from[a]) between.push_back(a);
                    std::reverse(between.begin(), between.end());
                }
                for (int a : between) {
                    if (!inner.count(a)) return false;
                    poly.push_back(node_vertex(a));
                }
                e = end_of[goal];
            }
            if (e != first) return false;  // the pieces cross each other
            std::vector<uint32_t> sorted = poly;
            std::sort(sorted.begin(), sorted.end());
            if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
            polygons.push_back(std::move(poly));
        }
        // The face inside each loop goes round it the other way from the faces outside it.
        for (const auto& [p, loop] : loops) {
            std::vector<uint32_t> face;
            for (int x : loop.order) face.push_back(node_vertex(x));
            const std::size_t k = face.size();
            int way = 0;  // +1: the faces outside went along the loop's order, -1 against it
            for (const auto& poly : polygons)
                for (std::size_t i = 0; i < poly.size() && !way; ++i)
                    for (std::size_t j = 0; j < k && !way; ++j)
                        if (poly[i] == face[j]) {
                            const uint32_t next = poly[(i + 1) % poly.size()];
                            way = next == face[(j + 1) % k] ? 1 : next == face[(j + k - 1) % k] ? -1 : 0;
                        }
            if (!way) return false;
            if (way > 0) std::reverse(face.begin(), face.end());
            polygons.push_back(std::move(face));
        }
        std::vector<Tri> triangles;
        std::vector<std::size_t> first_of;
        if (!triangulate_sides(polygons, box, kMaxWedgePolygon, no_shared_outside_cell, triangles, first_of)) return false;
        if (polygons_cross(triangles, first_of, h)) return false;
        chain_edges_ += edges.size();
        out = std::move(triangles);
        return true;
    }

    /// A band's joined patch redone: an annulus round a closed crease whose crossings fell in
    /// cells with every node inside (a concave crease shallower than a cell: the pawn's head
    /// on its collar), so most have no segment and the gaps' trees, sharing the crossings
    /// between them, would compete for each other's cells. The crease cuts the annulus into
    /// two, each lofted from its boundary ring to the crease (loft). Refused unless the
    /// block's cells with triangles are all joined and hold no other crossing or link, and
    /// the two rings are on the crease's two sides.
    bool build_band(const Wedge& band, std::vector<uint32_t>& patch,
                    const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of, std::vector<Tri>& out) {
        const double h = band.block.h;
        const std::set<int> on_crease(band.cycle.begin(), band.cycle.end());
        for (uint64_t id : band.cells)
            if (crease_holdings(id, on_crease).second) return false;
        auto in_group = [&](uint64_t id) { return std::binary_search(band.cells.begin(), band.cells.end(), id); };
        for (uint64_t id : band.tube)
            if ((!has_patch_ || has_patch_(id)) && !in_group(id)) return false;  // its triangles could be crossed
        std::vector<uint32_t> crease;
        for (int x : band.cycle) {
            if (!patches_around_joined(positions_[crossings_[x].vertex], band.cells)) return false;
            crease.push_back(crossings_[x].vertex);
        }
        if (patch.empty()) return false;
        // The triangles redone: those within one cell of the crease, else within two, else all
        // the joined cells' (the rest stay; where a rim lies a cell beyond the crease, a strip
        // to the tube's boundary would cut across it: the pawn's collar at 41 nodes).
        // Distances up to two cells matter. Consecutive crease points lie on the faces of one
        // cell, a cell diagonal apart at most, so a segment that near has an end within four
        // cells: buckets four cells wide, each point's and the 26 around it.
        const double bucket = 4 * h;
        auto key = [&](const Vec& p, int dx, int dy, int dz) {
            return std::array<long, 3>{long(std::floor(p[0] / bucket)) + dx, long(std::floor(p[1] / bucket)) + dy,
                                       long(std::floor(p[2] / bucket)) + dz};
        };
        std::map<std::array<long, 3>, std::vector<std::size_t>> buckets;
        for (std::size_t k = 0; k < crease.size(); ++k) buckets[key(positions_[crease[k]], 0, 0, 0)].push_back(k);
        std::vector<double> distance(patch.size(), std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < patch.size(); ++i) {
            const Vec c = centroid(mesh_.triangles[patch[i]]);
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        if (const auto it = buckets.find(key(c, dx, dy, dz)); it != buckets.end())
                            for (std::size_t k : it->second)
                                for (std::size_t other : {(k + crease.size() - 1) % crease.size(), (k + 1) % crease.size()})
                                    distance[i] = std::min(distance[i], segment_distance(c, positions_[crease[k]], positions_[crease[other]]));
        }
        // Each triangle's neighbours across its edges, within the patch (patch.size(): none).
        std::vector<std::pair<std::pair<uint32_t, uint32_t>, std::size_t>> edges;  // directed edge → triangle
        edges.reserve(patch.size() * 3);
        for (std::size_t i = 0; i < patch.size(); ++i)
            for (int e = 0; e < 3; ++e) {
                const Tri& t = mesh_.triangles[patch[i]];
                edges.push_back({{t[e], t[(e + 1) % 3]}, i});
            }
        std::sort(edges.begin(), edges.end());
        std::vector<std::array<std::size_t, 3>> across(patch.size());
        for (std::size_t i = 0; i < patch.size(); ++i)
            for (int e = 0; e < 3; ++e) {
                const Tri& t = mesh_.triangles[patch[i]];
                const std::pair<uint32_t, uint32_t> back{t[(e + 1) % 3], t[e]};
                const auto it = std::lower_bound(edges.begin(), edges.end(), std::pair{back, std::size_t{0}});
                across[i][e] = it != edges.end() && it->first == back ? it->second : patch.size();
            }
        // Tried in turn: the triangles within one cell of the crease, within two, then all. Each
        // set smoothed so its rings run along the crease, not out and back (a strip's triangle
        // on such a step would stand on its edge): a triangle of the set with one neighbour in
        // it (a spike) leaves, one outside with two or more (a notch) joins.
        std::size_t tried = 0;  // the triangles of the last try (a wider one may take no more)
        for (const double within : {1.0, 2.0, std::numeric_limits<double>::infinity()}) {
            std::vector<char> in(patch.size());
            for (std::size_t i = 0; i < patch.size(); ++i) in[i] = distance[i] <= within * h;
            for (int round = 0; round < 4; ++round) {
                bool changed = false;
                for (std::size_t i = 0; i < patch.size(); ++i) {
                    int inside = 0;
                    for (std::size_t j : across[i]) inside += j < patch.size() && in[j];
                    if ((in[i] && inside <= 1) || (!in[i] && inside >= 2)) in[i] = !in[i], changed = true;
                }
                if (!changed) break;
            }
            std::vector<uint32_t> redone, kept;
            for (std::size_t i = 0; i < patch.size(); ++i) (in[i] ? redone : kept).push_back(patch[i]);
            if (redone.empty() || redone.size() == tried) continue;
            tried = redone.size();
            if (!loft_band(band, redone, kept, crease, patch_of, out)) continue;
            patch = std::move(redone);
            return true;
        }
        return false;
    }

    /// Distance from p to the segment ab.
    static double segment_distance(const Vec& p, const Vec& a, const Vec& b) {
        const Vec ab = sub(b, a);
        const double length2 = dot(ab, ab);
        const double t = length2 > 0 ? std::clamp(dot(sub(p, a), ab) / length2, 0.0, 1.0) : 0.0;
        return norm(sub(p, Vec{a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]}));
    }

    /// Band's triangles `redone` replaced by two strips, from each of their two boundary rings
    /// to the crease; `kept` the joined cells' other triangles, which they must not cross.
    bool loft_band(const Wedge& band, const std::vector<uint32_t>& redone, const std::vector<uint32_t>& kept,
                   const std::vector<uint32_t>& crease,
                   const std::function<std::optional<std::vector<uint32_t>>(uint64_t)>& patch_of, std::vector<Tri>& out) {
        const Cell& box = band.block;
        const double h = box.h;
        std::vector<std::vector<uint32_t>> rings;
        long euler = 0;
        if (!boundary_rings(redone, box, rings, euler) || rings.size() != 2 || euler != 0) return false;
        // A ring point is within radius + 1 cells of a crease point's cell along each axis.
        const double reach = (band.radius + 2) * std::sqrt(3.0) * h;
        std::vector<Tri> triangles;
        std::vector<std::size_t> first_of;
        int sides[2] = {0, 0};  // which way round the crease each ring's loft went
        for (int r = 0; r < 2; ++r) {
            first_of.push_back(triangles.size());
            std::vector<Tri> best;
            double least = std::numeric_limits<double>::infinity();
            for (int way : {1, -1}) {
                std::vector<uint32_t> q = crease;
                if (way < 0) std::reverse(q.begin(), q.end());
                std::vector<Tri> lofted;
                double area = 0;
                if (loft(rings[std::size_t(r)], q, h, reach, lofted, area) && area < least)
                    best = std::move(lofted), least = area, sides[r] = way;
            }
            if (best.empty()) return false;
            triangles.insert(triangles.end(), best.begin(), best.end());
        }
        first_of.push_back(triangles.size());
        if (sides[0] == sides[1] || polygons_cross(triangles, first_of, h)) return false;
        // Nor may they cross the triangles of the cells around the tube (the tube is not convex:
        // a strip between two of its faces could leave it).
        const std::set<uint64_t> wider = tube_around(band.cycle, band.radius + 1);
        std::vector<Tri> around;
        for (uint32_t t : kept) around.push_back(mesh_.triangles[t]);
        for (uint64_t id : wider)
            if (!std::binary_search(band.tube.begin(), band.tube.end(), id))
                if (const auto near = patch_of(id))
                    for (uint32_t t : *near) around.push_back(mesh_.triangles[t]);
        if (triangles_cross(triangles, around, h)) return false;
        for (uint64_t id : band.left_out) {  // redone after the band, within their own boxes
            const Cell cell = cell_box(id);
            for (const Tri& t : triangles)
                if (triangle_enters_box(positions_[t[0]], positions_[t[1]], positions_[t[2]], cell.lo, cell.hi)) return false;
        }
        std::set<std::pair<uint32_t, uint32_t>> directed;  // each edge at most once each way
        for (const Tri& t : triangles)
            for (int e = 0; e < 3; ++e)
                if (!directed.insert({t[e], t[(e + 1) % 3]}).second) return false;
        chain_edges_ += band.cycle.size();
        out = std::move(triangles);
        return true;
    }

    /// A strip triangle's area, or infinity where it is degenerate, faces against its
    /// vertices' normals, has an edge longer than `reach` (most pairs of points are ruled out
    /// before the field is evaluated), or leaves the surface: its centroid and edge midpoints
    /// within kMaxBandDistance cells (a strip two cells wide must not cut across a rim beside
    /// the crease, the pawn's collar at 41 nodes).
    /// `midpoints` remembers each edge's answer: the dynamic programs ask for every edge of a
    /// side or crease once per point of the other.
    double strip_area(uint32_t a, uint32_t b, uint32_t c, double h, double reach,
                      std::unordered_map<uint64_t, bool>& midpoints) const {
        const double inf = std::numeric_limits<double>::infinity();
        const Vec &u = positions_[a], &v = positions_[b], &w = positions_[c];
        if (norm(sub(u, v)) > reach || norm(sub(v, w)) > reach || norm(sub(w, u)) > reach) return inf;
        const Vec tn = area_normal({a, b, c});
        Vec normals{0, 0, 0};
        for (uint32_t x : {a, b, c})
            for (int k = 0; k < 3; ++k) normals[k] += normals_[x][k];
        const double area = norm(tn) / 2;
        if (!(area >= kMinChainArea * h * h) || !(dot(tn, normals) > 0)) return inf;
        if (!near_surface(centroid({a, b, c}), kMaxBandDistance * h)) return inf;
        for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            const auto [it, fresh] = midpoints.try_emplace(uint64_t(std::min(x, y)) << 32 | std::max(x, y), false);
            if (fresh) {
                const Vec &p = positions_[x], &q = positions_[y];
                it->second = near_surface(midpoint(p, q), kMaxBandDistance * h);
            }
            if (!it->second) return inf;
        }
        return area;
    }

    /// The strip between a patch's boundary ring and a closed crease going round the same way
    /// (the patch on the ring's left): each triangle two points of one and one of the other,
    /// the least total area over all such strips (dynamic programming, as contours are
    /// joined into surfaces), none degenerate or facing against its vertices' normals. Then
    /// checked to be a graph over the plane across its mean normal, as triangulate() does for a
    /// polygon: its triangles keep their orientation there and neither loop crosses itself or
    /// the other, so it cannot fold or cross itself.
    bool loft(const std::vector<uint32_t>& ring, const std::vector<uint32_t>& crease, double h, double reach,
              std::vector<Tri>& out, double& total) const {
        const std::size_t m = ring.size(), n = crease.size();
        if (m < 3 || n < 3 || (m + 1) * (n + 1) > kMaxLoftSize) return false;
        std::size_t shift = 0;  // the strip starts from the ring's first point to the crease's nearest
        for (std::size_t j = 1; j < n; ++j)
            if (norm(sub(positions_[crease[j]], positions_[ring[0]])) < norm(sub(positions_[crease[shift]], positions_[ring[0]])))
                shift = j;
        auto p = [&](std::size_t i) { return ring[i % m]; };
        auto q = [&](std::size_t j) { return crease[(j + shift) % n]; };
        const double inf = std::numeric_limits<double>::infinity();
        std::unordered_map<uint64_t, bool> midpoints;
        auto area_of = [&](uint32_t a, uint32_t b, uint32_t c) { return strip_area(a, b, c, h, reach, midpoints); };
        const std::size_t width = n + 1;
        std::vector<double> cost((m + 1) * width, inf);
        std::vector<char> along_ring((m + 1) * width, 0);  // the last step: 1 along the ring, 0 along the crease
        cost[0] = 0;
        for (std::size_t i = 0; i <= m; ++i)
            for (std::size_t j = 0; j <= n; ++j) {
                double& c = cost[i * width + j];
                if (i > 0 && cost[(i - 1) * width + j] < inf) {
                    const double next = cost[(i - 1) * width + j] + area_of(p(i - 1), p(i), q(j));
                    if (next < c) c = next, along_ring[i * width + j] = 1;
                }
                if (j > 0 && cost[i * width + j - 1] < inf) {
                    const double next = cost[i * width + j - 1] + area_of(p(i), q(j), q(j - 1));
                    if (next < c) c = next, along_ring[i * width + j] = 0;
                }
            }
        total = cost[m * width + n];
        if (!(total < inf)) return false;
        std::vector<Tri> triangles;
        for (std::size_t i = m, j = n; i > 0 || j > 0;) {
            if (along_ring[i * width + j]) triangles.push_back({p(i - 1), p(i), q(j)}), --i;
            else triangles.push_back({p(i), q(j), q(j - 1)}), --j;
        }
        Vec normal{0, 0, 0};
        for (const Tri& t : triangles) {
            const Vec tn = area_normal(t);
            for (int a = 0; a < 3; ++a) normal[a] += tn[a];
        }
        const double length = norm(normal);
        if (!(length > 0)) return false;
        for (double& c : normal) c /= length;
        for (const Tri& t : triangles)
            if (!(dot(area_normal(t), normal) / 2 >= kMinChainProjectedArea * h * h)) return false;
        if (!loops_simple({ring, crease}, normal, h)) return false;
        out = std::move(triangles);
        return true;
    }

    /// Whether a triangle of `ours` crosses one of `theirs` (an edge of one through the other;
    /// shared vertices and edges do not count), their bounding boxes compared first.
    bool triangles_cross(const std::vector<Tri>& ours, const std::vector<Tri>& theirs, double h) const {
        const double eps = 1e-12 * h * h * h;
        const auto& P = positions_;
        auto bounds = [&](const Tri& t) {
            std::array<Vec, 2> b{P[t[0]], P[t[0]]};
            for (uint32_t v : t)
                for (int a = 0; a < 3; ++a) b[0][a] = std::min(b[0][a], P[v][a]), b[1][a] = std::max(b[1][a], P[v][a]);
            return b;
        };
        for (const Tri& x : ours) {
            const auto bx = bounds(x);
            for (const Tri& y : theirs) {
                const auto by = bounds(y);
                bool apart = false;
                for (int a = 0; a < 3; ++a) apart |= bx[1][a] < by[0][a] || by[1][a] < bx[0][a];
                if (apart) continue;
                for (int e = 0; e < 3; ++e)
                    if (segment_through_triangle(P[x[e]], P[x[(e + 1) % 3]], P[y[0]], P[y[1]], P[y[2]], eps, EndOnPlane::misses) ||
                        segment_through_triangle(P[y[e]], P[y[(e + 1) % 3]], P[x[0]], P[x[1]], P[x[2]], eps, EndOnPlane::misses))
                        return true;
            }
        }
        return false;
    }

    /// Whether a triangle of one polygon crosses one of another (first_of: where each
    /// polygon's triangles start, then the end): the two sides of an edge must not cross.
    bool polygons_cross(const std::vector<Tri>& triangles, const std::vector<std::size_t>& first_of, double h) const {
        const double eps = 1e-12 * h * h * h;
        const auto& P = positions_;
        for (std::size_t p = 0; p + 2 < first_of.size(); ++p)
            for (std::size_t s = first_of[p]; s < first_of[p + 1]; ++s)
                for (std::size_t t = first_of[p + 1]; t < triangles.size(); ++t) {
                    const Tri &x = triangles[s], &y = triangles[t];
                    for (int e = 0; e < 3; ++e)
                        if (segment_through_triangle(P[x[e]], P[x[(e + 1) % 3]], P[y[0]], P[y[1]], P[y[2]], eps, EndOnPlane::misses) ||
                            segment_through_triangle(P[y[e]], P[y[(e + 1) % 3]], P[x[0]], P[x[1]], P[x[2]], eps, EndOnPlane::misses))
                            return true;
                }
        return false;
    }

    /// Triangulates the polygons one after another, each new edge refused where an earlier
    /// polygon already has it: along a nearly straight chain the two sides' least-area fans can
    /// pick the same chord, and two folds on one edge make it non-manifold (Chainik's flat faces).
    /// `allowed` (optional) refuses more edges. first_of: where each polygon's triangles start.
    bool triangulate_sides(const std::vector<std::vector<uint32_t>>& polygons, const Cell& cell, int max_vertices,
                           const std::function<bool(uint32_t, uint32_t)>& allowed, std::vector<Tri>& triangles,
                           std::vector<std::size_t>& first_of) const {
        std::set<std::pair<uint32_t, uint32_t>> used;
        auto fresh = [&](uint32_t u, uint32_t v) {
            return !used.count({std::min(u, v), std::max(u, v)}) && (!allowed || allowed(u, v));
        };
        for (const auto& poly : polygons) {
            first_of.push_back(triangles.size());
            if (!triangulate(poly, cell, triangles, max_vertices, fresh)) return false;
            for (std::size_t t = first_of.back(); t < triangles.size(); ++t)
                for (int e = 0; e < 3; ++e) {
                    const uint32_t u = triangles[t][e], v = triangles[t][(e + 1) % 3];
                    used.insert({std::min(u, v), std::max(u, v)});
                }
        }
        first_of.push_back(triangles.size());
        std::set<std::pair<uint32_t, uint32_t>> directed;  // each edge at most once each way
        for (const Tri& t : triangles)
            for (int e = 0; e < 3; ++e)
                if (!directed.insert({t[e], t[(e + 1) % 3]}).second) return false;
        return true;
    }

    /// Each crossing put into the boundary segment of `loop` chosen for it (choose_segments),
    /// as insert[segment]; two may share one (two edges leaving a corner just past the face:
    /// the FLOZ3 plate's at 57 nodes, 0.002 below it; both edges into its tip across the face
    /// of the tip's cell at 29), in their order along it, which the neighbour walking the
    /// segment the other way meets reversed: the same boundary. False when a crossing's
    /// segment is not on the loop, or the boundary with the crossings in would cross itself
    /// in a face's plane (the neighbour across the face sees it).
    bool put_into_segments(const std::vector<uint32_t>& loop, const std::vector<int>& crossings, double h,
                           std::vector<std::vector<int>>& insert) const {
        const std::size_t n = loop.size();
        const double tolerance = 1e-9 * h;
        insert.assign(n, {});
        for (int x : crossings) {
            const std::size_t at = segment_index(loop, crossings_[x].segment);
            if (at == n) return false;
            insert[at].push_back(x);
        }
        std::vector<std::vector<Vec>> pieces(n);  // each segment with its crossings in
        for (std::size_t i = 0; i < n; ++i) {
            const Vec &a = positions_[loop[i]], &b = positions_[loop[(i + 1) % n]];
            const Vec ab = sub(b, a);
            std::sort(insert[i].begin(), insert[i].end(), [&](int x, int y) {
                return dot(sub(positions_[crossings_[x].vertex], a), ab) < dot(sub(positions_[crossings_[y].vertex], a), ab);
            });
            pieces[i].push_back(a);
            for (int x : insert[i]) pieces[i].push_back(positions_[crossings_[x].vertex]);
            pieces[i].push_back(b);
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (insert[i].empty()) continue;
            const int axis = int(crossings_[insert[i].front()].face % 3);
            const double plane = positions_[crossings_[insert[i].front()].vertex][axis];
            const int u = axis == 0 ? 1 : 0, w = axis == 2 ? 1 : 2;
            auto flat = [&](const Vec& p) { return std::array<double, 2>{p[u], p[w]}; };
            for (std::size_t j = 0; j < n; ++j) {
                const Vec &c = positions_[loop[j]], &d = positions_[loop[(j + 1) % n]];
                if (std::fabs(c[axis] - plane) > tolerance || std::fabs(d[axis] - plane) > tolerance) continue;
                for (std::size_t p = 0; p + 1 < pieces[i].size(); ++p)
                    for (std::size_t r = 0; r + 1 < pieces[j].size(); ++r) {
                        if (j == i && (r == p || r + 1 == p || p + 1 == r)) continue;  // itself, or its neighbours
                        if (segments_cross_2d(flat(pieces[i][p]), flat(pieces[i][p + 1]), flat(pieces[j][r]),
                                              flat(pieces[j][r + 1]), 1e-12 * h * h))
                            return false;
                    }
            }
        }
        return true;
    }

    /// Cell `id`'s patch with its crossings put on its boundary and cut along its feature
    /// edges (the traced links, or the spokes from its corner). False if any test fails.
    bool build_cell(uint64_t id, const std::vector<uint32_t>* patch, std::vector<Tri>& out,
                    const std::vector<uint64_t>* group = nullptr) {
        std::vector<int> crossings = crossings_in(id);
        const auto apex_it = apex_.find(id);
        const Cell cell = group ? joined_box(*group) : cell_box(id);
        if (group) {
            // Crossings on the faces between the cells are inside the fan.
            for (uint64_t g : *group) {
                const std::vector<int> more = crossings_in(g);
                crossings.insert(crossings.end(), more.begin(), more.end());
            }
            std::sort(crossings.begin(), crossings.end());
            crossings.erase(std::unique(crossings.begin(), crossings.end()), crossings.end());
            std::erase_if(crossings, [&](int x) {
                if (crossings_[x].on_mesh_vertex) return false;
                const auto two = cells_of_face(crossings_[x].face);
                return std::find(group->begin(), group->end(), two[0]) != group->end() &&
                       std::find(group->begin(), group->end(), two[1]) != group->end();
            });
        }
        if (crossings.empty() && apex_it == apex_.end()) return true;  // nothing to change
        if (!patch) return false;
        const double h = cell.h, tolerance = 1e-9 * h;
        std::vector<uint32_t> loop;
        if (!boundary_loop(*patch, cell, loop)) return false;
        const std::size_t n = loop.size();

        std::vector<int> on_faces;
        for (int x : crossings)
            if (!crossings_[x].on_mesh_vertex) on_faces.push_back(x);
        std::vector<std::vector<int>> insert;
        if (!put_into_segments(loop, on_faces, h, insert)) return false;
        std::vector<uint32_t> ring;
        std::map<int, std::size_t> position;  // crossing → its index in the ring
        for (std::size_t i = 0; i < n; ++i) {
            for (int x : crossings)
                if (crossings_[x].on_mesh_vertex && crossings_[x].vertex == loop[i]) position[x] = ring.size();
            ring.push_back(loop[i]);
            for (int x : insert[i]) {
                position[x] = ring.size();
                ring.push_back(crossings_[x].vertex);
            }
        }
        const std::size_t m = ring.size();

        std::vector<Tri> triangles;
        std::size_t feature_edges = 0;
        if (apex_it != apex_.end()) {
            // A corner: a fan from it over the ring, a graph along one of the faces' normals.
            std::vector<uint32_t> sorted_ring = ring;
            std::sort(sorted_ring.begin(), sorted_ring.end());
            if (std::adjacent_find(sorted_ring.begin(), sorted_ring.end()) != sorted_ring.end()) return false;  // pinched
            const uint32_t apex = apex_it->second;
            const Vec& c = positions_[apex];
            if (!cell.contains(c, 1e-12 * h)) return false;
            std::vector<Tri> star;
            for (std::size_t i = 0; i < m; ++i) star.push_back({apex, ring[i], ring[(i + 1) % m]});
            Vec patch_normal{0, 0, 0};
            for (uint32_t t : *patch) {
                const Tri& tri = mesh_.triangles[t];
                const Vec tn = cross(sub(mesh_.vertices[tri[1]], mesh_.vertices[tri[0]]),
                                     sub(mesh_.vertices[tri[2]], mesh_.vertices[tri[0]]));
                for (int a = 0; a < 3; ++a) patch_normal[a] += tn[a];
            }
            field_.at(c);
            std::vector<Vec> normals, directions;
            for (int e : apex_equations_[id]) {
                const Vec g = field_.gradient(e);
                const double l = norm(g);
                if (l > 0 && finite(g)) normals.push_back({-g[0] / l, -g[1] / l, -g[2] / l});
            }
            Vec faces_sum{0, 0, 0};
            for (const Vec& v : normals)
                for (int a = 0; a < 3; ++a) faces_sum[a] += v[a];
            const double turn = dot(faces_sum, patch_normal) < 0 ? -1 : 1;
            auto add_direction = [&](Vec d) {
                const double length = norm(d);
                if (!(length > 0)) return;
                for (double& x : d) x *= turn / length;
                directions.push_back(d);
            };
            add_direction(faces_sum);
            for (std::size_t i = 0; i < normals.size(); ++i) {
                add_direction(normals[i]);
                for (std::size_t j = i + 1; j < normals.size(); ++j)
                    add_direction({normals[i][0] + normals[j][0], normals[i][1] + normals[j][1], normals[i][2] + normals[j][2]});
            }
            add_direction({patch_normal[0] * turn, patch_normal[1] * turn, patch_normal[2] * turn});
            const int apex_faces = group ? 0 : cell.faces_of(c, tolerance);  // a group's corner is inside its box
            for (uint32_t v : ring) {  // a spoke on a face: only where no other cell meshes that face
                const int shared = apex_faces & cell.faces_of(positions_[v], tolerance);
                if (shared && !boundary_edge_free(id, shared)) return false;
            }
            Vec direction;
            if (!graph_direction(star, apex, positions_, directions, h, direction)) return false;
            triangles = std::move(star);
            feature_edges = crossings.size();
        } else {
            // The traced links cut the ring into polygons; crossings without a link stay ring vertices.
            std::vector<std::pair<std::size_t, std::size_t>> chords;
            std::vector<std::pair<int, int>> links = links_[id];
            if (group) {  // a group's: the links of all its cells
                for (uint64_t g : *group)
                    if (const auto more = links_.find(g); more != links_.end())
                        links.insert(links.end(), more->second.begin(), more->second.end());
                std::sort(links.begin(), links.end());
                links.erase(std::unique(links.begin(), links.end()), links.end());
            }
            for (const auto& [a, b] : links) {
                const auto ia = position.find(a), ib = position.find(b);
                if (ia == position.end() || ib == position.end()) continue;
                std::size_t i = std::min(ia->second, ib->second), j = std::max(ia->second, ib->second);
                if (j - i < 2 || (i == 0 && j == m - 1)) return false;  // joins neighbours on the ring
                const int shared = cell.faces_of(positions_[ring[i]], tolerance) & cell.faces_of(positions_[ring[j]], tolerance);
                if (shared && !(group ? chord_free(*group, positions_[ring[i]], positions_[ring[j]]) : boundary_edge_free(id, shared)))
                    return false;  // on a face another cell meshes
                chords.push_back({i, j});
            }
            for (std::size_t x = 0; x < chords.size(); ++x)
                for (std::size_t y = x + 1; y < chords.size(); ++y) {
                    const auto [a, b] = chords[x];
                    const auto [c, d] = chords[y];
                    const bool c_in = c > a && c < b, d_in = d > a && d < b;
                    if ((c_in != d_in && c != a && c != b && d != a && d != b) || (a == c && b == d)) return false;
                }
            feature_edges = chords.size();
            // Split: each chord, innermost first, takes the ring's vertices between its ends.
            std::sort(chords.begin(), chords.end(),
                      [](const auto& x, const auto& y) { return x.second - x.first < y.second - y.first; });
            std::vector<char> taken(m, 0);
            std::vector<std::vector<uint32_t>> polygons;
            for (const auto& [i, j] : chords) {
                std::vector<uint32_t> poly;
                for (std::size_t k = i; k <= j; ++k)
                    if (k == i || k == j || !taken[k]) poly.push_back(ring[k]);
                for (std::size_t k = i + 1; k < j; ++k) taken[k] = 1;
                polygons.push_back(std::move(poly));
            }
            std::vector<uint32_t> rest;
            for (std::size_t k = 0; k < m; ++k)
                if (!taken[k]) rest.push_back(ring[k]);
            polygons.push_back(std::move(rest));
            // A ring pinched at a vertex it holds twice (a clone's, choose_segments): two loops.
            for (std::size_t p = 0; p < polygons.size(); ++p)
                for (std::size_t i = 0; i < polygons[p].size(); ++i) {
                    auto& poly = polygons[p];
                    const auto again = std::find(poly.begin() + long(i) + 1, poly.end(), poly[i]);
                    if (again == poly.end()) continue;
                    std::vector<uint32_t> other(poly.begin() + long(i), again);
                    poly.erase(poly.begin() + long(i), again);
                    polygons.push_back(std::move(other));
                    --i;
                }
            std::vector<std::size_t> first_of;  // where each polygon's triangles start
            if (!triangulate_sides(polygons, cell, 64, {}, triangles, first_of)) return false;
            // Triangles of different polygons (the two sides of an edge) must not cross.
            if (polygons_cross(triangles, first_of, h)) return false;
        }
        chain_edges_ += feature_edges;  // an estimate for --stats: a cell redone later counts again
        out = std::move(triangles);
        return true;
    }

    static constexpr int kMaxTraceSteps = 1 << 22;
    static constexpr int kMaxStepsInCell = 64;
    static constexpr int kStepHalvings = 7;  ///< down to 1/256 of a cell
    static constexpr int kMaxWedgeRadius = 3;
    /// A band wider than two cells round its crease takes in more of the surface than the
    /// crease's rounding needs, and two lofts across it would cut the surface's curvature.
    static constexpr int kMaxBandRadius = 2;
    static constexpr std::size_t kMaxLoftSize = std::size_t(1) << 22;  ///< ring × crease points
    static constexpr int kMaxWedgePolygon = 256;
    /// A chamfer's vertices lie on a face within this many cells (marching tetrahedra keep
    /// theirs 1/1000 of an edge from the nodes, so off the surface by up to that).
    static constexpr double kChamferTolerance = 0.01;
    /// A chamfer's triangles lie within this many cells of its run of crossings (a wedge is
    /// cut at most a cell and a half from its edge), and so do its strips' edges.
    static constexpr double kChamferReach = 3;
    static constexpr std::size_t kMaxChamferRun = 4096;        ///< crossings
    static constexpr std::size_t kMaxChamferTriangles = 32;  ///< per crossing of the run
    static constexpr int kMaxChamferJoins = 16;  ///< runs joined through the crossings between them
    /// A thin cell's point on the wrong side of the finished mesh by more than this many
    /// cells is off it (RefineQuery); a point a hair across a face the pass put back is not
    /// a part left out (two of new_euclid's at 65 nodes, refined for nothing without it).
    static constexpr double kThinOffMesh = 0.05;

    mutable FeatureField field_;   ///< evaluation scratch: const checks evaluate too
    Mesh& mesh_;
    double min_[3], step_[3];
    int cells_[3];
    std::vector<Vec> positions_, normals_;  ///< the mesh's vertices, then crossings and corners
    std::vector<Crossing> crossings_;
    std::unordered_map<uint64_t, std::vector<int>> face_crossings_;
    std::unordered_map<uint64_t, std::vector<std::pair<int, int>>> links_;  ///< per cell
    std::unordered_set<uint64_t> visited_;
    std::set<uint64_t> end_cells_, tried_corner_;
    std::vector<char> is_cap_;  ///< by operation: one that cuts the model by a cap's plane (set_caps)
    std::function<bool(uint64_t)> has_patch_;
    std::vector<uint64_t> frozen_;
    std::vector<char> frozen_triangles_;  ///< per triangle of the mesh given: in a frozen cell
    std::set<uint64_t> edge_apex_tried_;
    /// Cells redone together, each mapped to all of them, their shared faces inside: around a
    /// corner on the lattice (the solid on both sides of a grid plane through it, fanned from
    /// it), beside a piece of edge on a face between two cells (plan_edge_groups), a cell of
    /// two sheets with the cell beyond them (plan_sheet_groups).
    std::map<uint64_t, std::vector<uint64_t>> groups_;
    std::set<int> nodes_passed_;  ///< crossings at grid nodes the curve passes diagonally (three axes)
    std::map<int, std::pair<uint64_t, uint32_t>> corner_tips_;  ///< a tip that was a corner's fan → its cell, vertex
    std::unordered_map<int, std::vector<int>> partners_;  ///< each crossing's linked crossings, in any cell
    std::vector<uint32_t> tips_;  ///< corners in cells with no triangles, and those that joined a tree
    std::unordered_map<int, int> tip_crossings_;              ///< a crossing in a tip's cell → the tip
    std::unordered_map<int, std::vector<int>> crossings_of_tip_;
    std::unordered_map<int, int> tip_at_;  ///< a crossing where a tip is → the tip
    std::vector<Wedge> wedges_;
    std::vector<Wedge> mid_edge_wedges_;  ///< trees without a tip, grouped after the others are built
    std::map<uint64_t, std::size_t> wedge_of_;            ///< a wedge's cells → the wedge
    std::set<uint64_t> banded_;                           ///< the cells of the bands redone
    std::vector<uint64_t> corner_cells_;
    std::map<uint64_t, uint32_t> apex_;
    std::map<uint64_t, std::vector<int>> apex_equations_;
    std::map<uint64_t, std::pair<std::vector<uint32_t>, std::vector<Tri>>> results_;  ///< old triangles, new
    std::size_t chain_edges_ = 0;
};

}  // namespace

bool sharpen_features(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh,
                      const std::vector<uint64_t>& triangle_cells, const DomainCaps& caps,
                      const std::vector<uint64_t>& frozen, FeatureStats* stats, RefineQuery* query,
                      std::vector<std::array<double, 3>>* crossings_left) {
    FeatureStats local;
    // A model with no edges of its own keeps marching tetrahedra's mesh, caps and all: where
    // the domain cuts a smooth field (the tanglecube on [-1, 1]³), its caps' rims would be its
    // only edges, and tracing them would cost three times the mesh (27.5 → 90 ms at 257 nodes).
    const std::vector<ir::NodeId> nodes = graph.reachable(root);
    if (std::none_of(nodes.begin(), nodes.end(), [&](ir::NodeId id) {
            ir::NodeId a, b;
            return FeatureField::operation(graph, id, a, b);
        })) {
        if (stats) *stats = local;
        // No edges to put back: every thin cell is refined.
        if (query) query->refine = query->thin_cells();
        return !query || query->refine.empty();
    }
    // The solid the mesh closes is the model's cut by its caps' planes: those planes are
    // operands too (MIN), so an edge that runs into a face ends in a corner on its cap, and the
    // caps' rims and the domain's edges are edges. Only faces the solid is cut by: where it
    // only touches the domain (the Steinmetz solid on [-1, 1]³), a plane a thousandth of a
    // cell inside would cut its edge into slivers.
    ir::Graph cut = graph;
    ir::NodeId cut_root = root;
    std::vector<ir::NodeId> cap_nodes;
    const Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
    for (int a = 0; a < 3; ++a)
        for (int upper = 0; upper < 2; ++upper) {
            if (!caps.faces[std::size_t(2 * a + upper)]) continue;
            const Axis& axis = *axes[a];
            const ir::NodeId at = cut.argument(a);
            const ir::NodeId plane = cut.constant(upper ? axis.max - caps.margin * axis.step() : axis.min + caps.margin * axis.step());
            cut_root = cut.binary(ir::Op::Min, cut_root, upper ? cut.binary(ir::Op::Sub, plane, at) : cut.binary(ir::Op::Sub, at, plane));
            cap_nodes.push_back(cut_root);
        }
    ChainBuilder builder(cut, cut_root, grid, mesh);
    builder.set_caps(cap_nodes);
    if (!frozen.empty()) {
        std::vector<char> frozen_triangles(mesh.triangles.size(), 0);
        for (std::size_t t = 0; t < frozen_triangles.size(); ++t)
            frozen_triangles[t] = std::binary_search(frozen.begin(), frozen.end(), triangle_cells[t]);
        builder.set_frozen(frozen, std::move(frozen_triangles));
    }
    if (builder.has_operations() && mesh.normals.size() == mesh.vertices.size()) {
        // Each cell's patch: the triangles order[begin, end) (a map of vectors would cost
        // more than the mesh on large models).
        std::vector<uint32_t> order(mesh.triangles.size());
        for (uint32_t t = 0; t < order.size(); ++t) order[t] = t;
        std::stable_sort(order.begin(), order.end(),
                         [&](uint32_t a, uint32_t b) { return triangle_cells[a] < triangle_cells[b]; });
        std::vector<std::pair<uint64_t, std::size_t>> starts;  // (cell, first index in order)
        for (std::size_t i = 0; i < order.size(); ++i)
            if (i == 0 || triangle_cells[order[i]] != triangle_cells[order[i - 1]]) starts.push_back({triangle_cells[order[i]], i});
        auto patch_at = [&](std::size_t s) {
            const std::size_t end = s + 1 < starts.size() ? starts[s + 1].second : order.size();
            return std::vector<uint32_t>(order.begin() + long(starts[s].second), order.begin() + long(end));
        };
        builder.set_patch_test([&](uint64_t cell) {
            const auto it = std::lower_bound(starts.begin(), starts.end(), std::pair<uint64_t, std::size_t>{cell, 0});
            return it != starts.end() && it->first == cell;
        });
        for (std::size_t s = 0; s < starts.size(); ++s) builder.seed(starts[s].first, patch_at(s), local);
        const auto patch_of = [&](uint64_t cell) -> std::optional<std::vector<uint32_t>> {
            const auto it = std::lower_bound(starts.begin(), starts.end(), std::pair<uint64_t, std::size_t>{cell, 0});
            if (it == starts.end() || it->first != cell) return std::nullopt;
            return patch_at(std::size_t(it - starts.begin()));
        };
        builder.build(patch_of);
        if (!builder.finish(patch_of, stats ? &local : nullptr, query, crossings_left)) return false;
    } else if (query) {
        query->refine = query->thin_cells();
        if (!query->refine.empty()) return false;
    }
    if (stats) *stats = local;
    return true;
}

}  // namespace fortu
