// interp/mesh_features.cpp — feature cells, their points by Newton's method, the fans and the
// flips across shared faces (the why is in mesh_features.hpp).
#include "interp/mesh_features.hpp"

#include "interp/lane_kernel.hpp"
#include "interp/tape.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <unordered_map>

namespace fortu {
namespace {

using Vec = std::array<double, 3>;
using Tri = std::array<uint32_t, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
bool finite(const Vec& a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

/// A cell is tested when two of its vertex normals are more than ~26° apart: at 128 cells a
/// smooth surface bends that much in a cell only where it is nearly singular itself.
constexpr double kFeatureCosine = 0.9;
/// An operand counts as vanishing in a cell when its first-order estimate reaches zero
/// within twice the cell's half diagonal (curved operands reach a little further).
constexpr double kReachFactor = 2.0;
/// A new triangle's area, in cell², at least: STL's float32 rounding (6e-8 relative) must
/// not make it degenerate, nor flip its projection.
constexpr double kMinArea = 1e-4;
constexpr double kMinProjectedArea = 1e-6;
/// Newton's method stops when a step is below this fraction of a cell; the point is then
/// on the feature to round-off (quadratic convergence, one step for planes).
constexpr double kStepTolerance = 1e-13;
/// Operands whose gradients make less than ~11° with the span of those already chosen are
/// not independent enough to solve for (a tangency, not an edge).
constexpr double kIndependence = 0.2;

/// Whether `id` is R0 written out as a formula, a + b ∓ sqrt(a² + b²) (RANOK scripts often spell
/// their R-operations so); a and b are set to its operands.
bool written_r0(const ir::Graph& graph, ir::NodeId id, ir::NodeId& a, ir::NodeId& b) {
    const ir::Node& n = graph.node(id);
    if (n.op != ir::Op::Sub && n.op != ir::Op::Add) return false;
    auto square_of = [&](ir::NodeId m) {
        const ir::Node& q = graph.node(m);
        if (q.op == ir::Op::Square) return q.args[0];
        if (q.op == ir::Op::Mul && q.args[0] == q.args[1]) return q.args[0];
        return ir::kNoNode;
    };
    for (int order = 0; order < (n.op == ir::Op::Add ? 2 : 1); ++order) {
        const ir::Node& sum = graph.node(n.args[order]);
        const ir::Node& root = graph.node(n.args[1 - order]);
        if (sum.op != ir::Op::Add || root.op != ir::Op::Sqrt) continue;
        const ir::Node& squares = graph.node(root.args[0]);
        if (squares.op != ir::Op::Add) continue;
        const ir::NodeId p = square_of(squares.args[0]), q = square_of(squares.args[1]);
        if ((p == sum.args[0] && q == sum.args[1]) || (p == sum.args[1] && q == sum.args[0])) {
            a = sum.args[0], b = sum.args[1];
            return true;
        }
    }
    return false;
}

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
            const ir::Node& n = graph.node(id);
            ir::NodeId a = n.args[0], b = n.args[1];
            if (!(ir::op_flags(n.op) & ir::kROperation) && n.op != ir::Op::Min && n.op != ir::Op::Max &&
                !written_r0(graph, id, a, b))
                continue;
            ops_.push_back({output(a), output(b), id});
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

/// Newton's method from p onto the common zero of `want` (2 or 3) of `equations` (outputs of
/// `field`), chosen afresh at each step, in order, as the first independent ones: the
/// minimum-norm step s = Jᵀ(JJᵀ)⁻¹F, as `fortu singular` takes onto an edge (for 3, the plain
/// Newton step onto a corner). True when it converged within `reach` of the start with every
/// equation zero to round-off.
bool solve_feature(FeatureField& field, const std::vector<int>& equations, int want, Vec& p, double h,
                   double reach) {
    const Vec start = p;
    for (int iteration = 0; iteration < 40; ++iteration) {
        field.at(p);
        std::vector<int> chosen;
        if (!choose_independent(field, equations, want, chosen)) return false;
        std::vector<Vec> rows;
        std::vector<double> rhs;
        for (int e : chosen) rows.push_back(field.gradient(e)), rhs.push_back(field.value(e));
        // (J Jᵀ) λ = F by Gaussian elimination with pivoting (want ≤ 3), then s = Jᵀ λ.
        double m[3][4];
        for (int i = 0; i < want; ++i) {
            for (int j = 0; j < want; ++j) m[i][j] = dot(rows[i], rows[j]);
            m[i][3] = rhs[i];
        }
        for (int c = 0; c < want; ++c) {
            int pivot = c;
            for (int r = c + 1; r < want; ++r)
                if (std::fabs(m[r][c]) > std::fabs(m[pivot][c])) pivot = r;
            std::swap(m[c], m[pivot]);
            if (!(std::fabs(m[c][c]) > 0)) return false;
            for (int r = 0; r < want; ++r) {
                if (r == c) continue;
                const double f = m[r][c] / m[c][c];
                for (int k = c; k < 4; ++k) m[r][k] -= f * m[c][k];
            }
        }
        Vec step{0, 0, 0};
        for (int i = 0; i < want; ++i)
            for (int k = 0; k < 3; ++k) step[k] += m[i][3] / m[i][i] * rows[i][k];
        for (int k = 0; k < 3; ++k) p[k] -= step[k];
        if (!finite(p) || norm(sub(p, start)) > reach) return false;
        if (norm(step) <= kStepTolerance * h) {
            field.at(p);
            for (int e : equations) {
                const double g = norm(field.gradient(e));
                if (!(std::fabs(field.value(e)) <= 1e-9 * h * (1 + (std::isfinite(g) ? g : 0)))) return false;
            }
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
};

/// A feature vertex and the triangles around it (each stored with the vertex first).
struct Fan {
    uint64_t cell;
    uint32_t vertex;               ///< its index in the final vertex list (before compaction)
    Vec point, direction;          ///< direction: one the star is a graph along
    std::vector<Vec> directions;   ///< the ones to try: the feature's faces' normals, their sums
    std::vector<int> operations;   ///< the R-operations whose edges meet here
    std::vector<std::size_t> triangles;  ///< indices into the new-triangle list
};

/// Whether the triangles around `apex` (each starting with it), projected on the plane
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

Tri rotate_to(const Tri& t, uint32_t first) {
    if (t[1] == first) return {t[1], t[2], t[0]};
    if (t[2] == first) return {t[2], t[0], t[1]};
    return t;
}

class Sharpener {
public:
    Sharpener(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh)
        : field_(graph, root), mesh_(mesh) {
        const Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
        for (int a = 0; a < 3; ++a) {
            min_[a] = axes[a]->min;
            step_[a] = axes[a]->step();
            cells_[a] = axes[a]->nodes - 1;
        }
        positions_ = mesh.vertices;
        removed_.assign(mesh.triangles.size(), 0);
    }

    bool has_operations() const { return !field_.operations().empty(); }

    Cell cell_box(uint64_t id) const {
        const uint64_t c[3] = {id % uint64_t(cells_[0]), id / uint64_t(cells_[0]) % uint64_t(cells_[1]),
                               id / (uint64_t(cells_[0]) * uint64_t(cells_[1]))};
        Cell cell;
        cell.h = 0;
        for (int a = 0; a < 3; ++a) {
            cell.lo[a] = min_[a] + double(c[a]) * step_[a];
            cell.hi[a] = min_[a] + double(c[a] + 1) * step_[a];
            cell.h = std::max(cell.h, step_[a]);
        }
        return cell;
    }

    /// The patch of cell `id` (its triangles `patch`) replaced by a fan, if the cell holds a
    /// feature and every test passes.
    /// `neighbour`: the cell is next to a feature cell, and is tried whatever its normals (an
    /// edge that only clips a cell leaves it with a patch on one face).
    bool try_cell(uint64_t id, const std::vector<uint32_t>& patch, bool neighbour, FeatureStats& stats) {
        double lowest = 1;
        std::vector<uint32_t> vertices;
        for (uint32_t t : patch)
            for (uint32_t v : mesh_.triangles[t]) vertices.push_back(v);
        std::sort(vertices.begin(), vertices.end());
        vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
        for (std::size_t i = 0; i < vertices.size() && lowest >= kFeatureCosine; ++i)
            for (std::size_t j = i + 1; j < vertices.size(); ++j)
                lowest = std::min(lowest, dot(mesh_.normals[vertices[i]], mesh_.normals[vertices[j]]));
        if (lowest >= kFeatureCosine && !neighbour) return false;
        ++stats.cells_tested;
        const Cell cell = cell_box(id);
        const double margin = 1e-12 * cell.h;

        // The operations whose two operands both reach zero in the cell.
        Vec centre;
        for (int a = 0; a < 3; ++a) centre[a] = (cell.lo[a] + cell.hi[a]) / 2;
        const double half_diagonal = norm(sub(cell.hi, cell.lo)) / 2;
        field_.at(centre);
        auto reaches_zero = [&](int i) {
            const double g = norm(field_.gradient(i));
            return std::isfinite(g) && std::fabs(field_.value(i)) <= kReachFactor * g * half_diagonal;
        };
        std::vector<int> candidates;
        const auto& ops = field_.operations();
        for (std::size_t k = 0; k < ops.size(); ++k)
            if (reaches_zero(ops[k].a) && reaches_zero(ops[k].b)) candidates.push_back(int(k));
        if (candidates.empty()) return false;

        Vec seed{0, 0, 0};
        for (uint32_t v : vertices)
            for (int a = 0; a < 3; ++a) seed[a] += mesh_.vertices[v][a] / double(vertices.size());
        auto on_model_boundary = [&](const Vec& p) {
            field_.at(p);
            double scale = 1;
            for (int k : candidates) {
                const double ga = norm(field_.gradient(ops[k].a)), gb = norm(field_.gradient(ops[k].b));
                scale += (std::isfinite(ga) ? ga : 0) + (std::isfinite(gb) ? gb : 0);
            }
            return std::fabs(field_.value(0)) <= 1e-8 * cell.h * scale;
        };
        const double reach = 2 * cell.h;
        Vec point{};
        std::vector<int> meeting, used;
        bool found = false, corner = false;
        if (candidates.size() >= 2) {  // a corner: three independent operands vanish together
            std::vector<int> equations, later;
            for (int k : candidates)
                for (int e : {ops[k].a, ops[k].b}) {
                    std::vector<int>& list = field_.operation_of(e) >= 0 ? later : equations;
                    if (std::find(list.begin(), list.end(), e) == list.end()) list.push_back(e);
                }
            equations.insert(equations.end(), later.begin(), later.end());
            Vec p = seed;
            if (solve_feature(field_, equations, 3, p, cell.h, reach) && cell.contains(p, margin) &&
                on_model_boundary(p)) {
                point = p, meeting = candidates, used = equations, found = corner = true;
            }
        }
        if (!found) {  // an edge: one operation's operands vanish together (one curve only)
            for (int k : candidates) {
                // The nearest point of the edge to the patch may lie outside the cell where the
                // edge only clips it: then from that point pulled back into the cell, again.
                Vec p = seed;
                bool inside = false;
                for (int round = 0; round < 4 && !inside; ++round) {
                    if (round > 0)
                        for (int a = 0; a < 3; ++a) p[a] = std::clamp(p[a], cell.lo[a], cell.hi[a]);
                    if (!solve_feature(field_, {ops[k].a, ops[k].b}, 2, p, cell.h, reach)) break;
                    inside = cell.contains(p, margin);
                }
                if (!inside || !on_model_boundary(p)) continue;
                if (found && norm(sub(p, point)) > 1e-9 * cell.h) return false;  // two curves: not one feature
                if (!found) point = p, used = {ops[k].a, ops[k].b};
                found = true;
                meeting.push_back(k);
            }
            if (!found) return false;
        }

        // The patch must be a disc whose inner vertices (on the cell's main diagonal) only
        // it uses; its boundary is then one loop on the cell's faces.
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        for (uint32_t t : patch)
            for (int k = 0; k < 3; ++k) ++directed[{mesh_.triangles[t][k], mesh_.triangles[t][(k + 1) % 3]}];
        std::map<uint32_t, uint32_t> next;
        std::size_t undirected = 0;
        for (const auto& [e, n] : directed) {
            if (n != 1) return false;
            if (directed.count({e.second, e.first})) {
                undirected += e.first < e.second;
                continue;
            }
            ++undirected;
            if (!next.emplace(e.first, e.second).second) return false;  // the boundary touches itself
        }
        if (long(vertices.size()) - long(undirected) + long(patch.size()) != 1) return false;
        std::vector<uint32_t> loop{next.begin()->first};
        while (loop.size() <= next.size()) {
            const auto it = next.find(loop.back());
            if (it == next.end()) return false;
            if (it->second == loop.front()) break;
            loop.push_back(it->second);
        }
        if (loop.size() != next.size()) return false;
        for (uint32_t v : vertices)
            if (!next.count(v) && !cell.contains(mesh_.vertices[v], -1e-9 * cell.h)) return false;

        // Directions to look along: the mean of the feature's faces' outward normals (the
        // operands' unit gradients, turned to the patch's side), else the patch's mean normal.
        Vec patch_normal{0, 0, 0};
        for (uint32_t t : patch) {
            const Tri& tri = mesh_.triangles[t];
            const Vec n = cross(sub(mesh_.vertices[tri[1]], mesh_.vertices[tri[0]]),
                                sub(mesh_.vertices[tri[2]], mesh_.vertices[tri[0]]));
            for (int a = 0; a < 3; ++a) patch_normal[a] += n[a];
        }
        // The faces' outward normals (turned to the patch's side), their sum and the sums of
        // two: a corner's star can be a graph along one face's normal and not along the mean.
        std::vector<Vec> normals, directions;
        field_.at(point);
        std::vector<int> chosen;
        if (choose_independent(field_, used, corner ? 3 : 2, chosen))
            for (int e : chosen) {
                const Vec g = field_.gradient(e);
                normals.push_back({-g[0] / norm(g), -g[1] / norm(g), -g[2] / norm(g)});
            }
        Vec faces{0, 0, 0};
        for (const Vec& n : normals)
            for (int a = 0; a < 3; ++a) faces[a] += n[a];
        const double turn = dot(faces, patch_normal) < 0 ? -1 : 1;
        auto add_direction = [&](Vec d) {
            const double length = norm(d);
            if (!(length > 0)) return;
            for (double& c : d) c *= turn / length;
            directions.push_back(d);
        };
        add_direction(faces);
        for (std::size_t i = 0; i < normals.size(); ++i) {
            add_direction(normals[i]);
            for (std::size_t j = i + 1; normals.size() > 2 && j < normals.size(); ++j)
                add_direction({normals[i][0] + normals[j][0], normals[i][1] + normals[j][1], normals[i][2] + normals[j][2]});
        }
        add_direction({patch_normal[0] * turn, patch_normal[1] * turn, patch_normal[2] * turn});
        const uint32_t apex = uint32_t(positions_.size());
        positions_.push_back(point);
        std::vector<Tri> star;
        for (std::size_t i = 0; i < loop.size(); ++i) star.push_back({apex, loop[i], loop[(i + 1) % loop.size()]});
        Vec direction{0, 0, 0};
        bool graph = false;
        graph = graph_direction(star, apex, positions_, directions, cell.h, direction);
        if (!graph) {
            positions_.pop_back();
            return false;
        }
        Fan fan{id, apex, point, direction, std::move(directions), meeting, {}};
        for (const Tri& t : star) {
            fan.triangles.push_back(new_triangles_.size());
            new_triangles_.push_back(t);
            alive_.push_back(1);
        }
        for (uint32_t t : patch) removed_[t] = 1;
        (corner ? stats.corner_vertices : stats.edge_vertices) += 1;
        fan_at_[id] = fans_.size();
        fans_.push_back(std::move(fan));
        return true;
    }

    /// Joins the feature vertices of fans `a` and `b` (b the next cell along `axis`) by
    /// flipping the fan triangles on their shared face's piece of boundary.
    bool try_join(std::size_t ia, std::size_t ib, int axis) {
        Fan& A = fans_[ia];
        Fan& B = fans_[ib];
        bool shared = false;
        for (int k : A.operations) shared |= std::find(B.operations.begin(), B.operations.end(), k) != B.operations.end();
        if (!shared) return false;
        const Cell ca = cell_box(A.cell);
        const double plane = ca.hi[axis], tolerance = 1e-9 * ca.h;
        auto on_face = [&](uint32_t v, bool strictly) {
            if (v >= mesh_.vertices.size()) return false;  // a feature vertex
            const Vec& p = positions_[v];
            if (std::fabs(p[axis] - plane) > tolerance) return false;
            for (int a = 0; a < 3; ++a) {
                if (a == axis) continue;
                if (strictly ? (p[a] <= ca.lo[a] + tolerance || p[a] >= ca.hi[a] - tolerance)
                             : (p[a] < ca.lo[a] - tolerance || p[a] > ca.hi[a] + tolerance))
                    return false;
            }
            return true;
        };
        // A's run on the face: its star's triangles (A, u, v) with u, v on it, in one chain.
        std::map<uint32_t, std::pair<uint32_t, std::size_t>> run;  // u → (v, triangle)
        for (std::size_t t : A.triangles) {
            if (!alive_[t]) continue;
            const Tri r = rotate_to(new_triangles_[t], A.vertex);
            if (on_face(r[1], false) && on_face(r[2], false)) run[r[1]] = {r[2], t};
        }
        if (run.empty()) return false;
        std::map<uint32_t, int> incoming;
        for (const auto& [u, vt] : run) ++incoming[vt.first];
        uint32_t start = 0;
        int starts = 0;
        for (const auto& [u, vt] : run)
            if (!incoming.count(u)) start = u, ++starts;
        if (starts != 1) return false;
        std::vector<uint32_t> chain{start};
        std::vector<std::size_t> removed;
        while (run.count(chain.back())) {
            const auto [v, t] = run[chain.back()];
            removed.push_back(t);
            chain.push_back(v);
            if (chain.size() > run.size() + 1) return false;
        }
        if (removed.size() != run.size()) return false;
        for (std::size_t i = 1; i + 1 < chain.size(); ++i)
            if (!on_face(chain[i], true)) return false;  // shared with cells beyond A and B
        // B's star must hold the same run backwards.
        for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
            bool seen = false;
            for (std::size_t t : B.triangles)
                if (alive_[t] && rotate_to(new_triangles_[t], B.vertex) == Tri{B.vertex, chain[i + 1], chain[i]}) {
                    removed.push_back(t);
                    seen = true;
                    break;
                }
            if (!seen) return false;
        }
        const Tri first{A.vertex, chain.front(), B.vertex}, second{B.vertex, chain.back(), A.vertex};
        Vec direction;
        for (int a = 0; a < 3; ++a) direction[a] = A.direction[a] + B.direction[a];
        const double length = norm(direction);
        if (!(length > 0)) return false;
        for (double& c : direction) c /= length;
        auto star_after = [&](const Fan& f) {
            std::vector<Tri> star;
            for (std::size_t t : f.triangles)
                if (alive_[t] && std::find(removed.begin(), removed.end(), t) == removed.end())
                    star.push_back(rotate_to(new_triangles_[t], f.vertex));
            star.push_back(rotate_to(first, f.vertex));
            star.push_back(rotate_to(second, f.vertex));
            return star;
        };
        // Each star a graph along the pair's mean direction or its own.
        auto graph = [&](const Fan& f) {
            const std::vector<Tri> star = star_after(f);
            std::vector<Vec> tries{direction};
            for (const Fan* g : {&A, &B}) tries.insert(tries.end(), g->directions.begin(), g->directions.end());
            Vec unused;
            return graph_direction(star, f.vertex, positions_, tries, ca.h, unused);
        };
        if (!graph(A) || !graph(B))
            return false;
        for (std::size_t t : removed) alive_[t] = 0;
        for (const Tri& t : {first, second}) {
            A.triangles.push_back(new_triangles_.size());
            B.triangles.push_back(new_triangles_.size());
            new_triangles_.push_back(t);
            alive_.push_back(1);
        }
        return true;
    }

    /// The cells sharing a face with cell `id`.
    std::vector<uint64_t> face_neighbours(uint64_t id) const {
        const uint64_t c[3] = {id % uint64_t(cells_[0]), id / uint64_t(cells_[0]) % uint64_t(cells_[1]),
                               id / (uint64_t(cells_[0]) * uint64_t(cells_[1]))};
        const uint64_t stride[3] = {1, uint64_t(cells_[0]), uint64_t(cells_[0]) * uint64_t(cells_[1])};
        std::vector<uint64_t> out;
        for (int a = 0; a < 3; ++a) {
            if (c[a] > 0) out.push_back(id - stride[a]);
            if (c[a] + 1 < uint64_t(cells_[a])) out.push_back(id + stride[a]);
        }
        return out;
    }

    void join_all(FeatureStats& stats) {
        for (std::size_t i = 0; i < fans_.size(); ++i) {
            const uint64_t id = fans_[i].cell;
            const uint64_t c[3] = {id % uint64_t(cells_[0]), id / uint64_t(cells_[0]) % uint64_t(cells_[1]),
                                   id / (uint64_t(cells_[0]) * uint64_t(cells_[1]))};
            const uint64_t stride[3] = {1, uint64_t(cells_[0]), uint64_t(cells_[0]) * uint64_t(cells_[1])};
            for (int axis = 0; axis < 3; ++axis) {
                if (c[axis] + 1 >= uint64_t(cells_[axis])) continue;
                const auto it = fan_at_.find(id + stride[axis]);
                if (it != fan_at_.end() && try_join(i, it->second, axis)) ++stats.joined_faces;
            }
        }
    }

    /// The mesh with the patches replaced and unused vertices dropped.
    void finish() {
        std::vector<Tri> triangles;
        for (std::size_t t = 0; t < mesh_.triangles.size(); ++t)
            if (!removed_[t]) triangles.push_back(mesh_.triangles[t]);
        for (std::size_t t = 0; t < new_triangles_.size(); ++t)
            if (alive_[t]) triangles.push_back(new_triangles_[t]);
        std::vector<Vec> normals = mesh_.normals;
        normals.resize(positions_.size());
        for (const Fan& f : fans_) normals[f.vertex] = f.direction;
        std::vector<uint32_t> renumber(positions_.size(), UINT32_MAX);
        for (const Tri& t : triangles)
            for (uint32_t v : t) renumber[v] = 0;
        Mesh out;
        for (std::size_t v = 0; v < positions_.size(); ++v) {
            if (renumber[v] == UINT32_MAX) continue;
            renumber[v] = uint32_t(out.vertices.size());
            out.vertices.push_back(positions_[v]);
            out.normals.push_back(normals[v]);
        }
        for (Tri& t : triangles)
            for (uint32_t& v : t) v = renumber[v];
        out.triangles = std::move(triangles);
        mesh_ = std::move(out);
    }

private:
    FeatureField field_;
    Mesh& mesh_;
    double min_[3], step_[3];
    int cells_[3];
    std::vector<Vec> positions_;              ///< the mesh's vertices, then the feature vertices
    std::vector<Tri> new_triangles_;
    std::vector<char> alive_;
    std::vector<char> removed_;  ///< old triangles replaced by fans
    std::vector<Fan> fans_;
    std::unordered_map<uint64_t, std::size_t> fan_at_;
};

}  // namespace

void sharpen_features(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh,
                      const std::vector<uint64_t>& triangle_cells, FeatureStats* stats) {
    FeatureStats local;
    Sharpener sharpener(graph, root, grid, mesh);
    if (sharpener.has_operations() && mesh.normals.size() == mesh.vertices.size()) {
        std::vector<uint32_t> order(mesh.triangles.size());
        for (uint32_t t = 0; t < order.size(); ++t) order[t] = t;
        std::stable_sort(order.begin(), order.end(),
                         [&](uint32_t a, uint32_t b) { return triangle_cells[a] < triangle_cells[b]; });
        // Each cell's patch: order[begin, end).
        std::unordered_map<uint64_t, std::pair<std::size_t, std::size_t>> patches;
        std::vector<uint64_t> cells;
        for (std::size_t i = 0; i < order.size();) {
            std::size_t j = i;
            while (j < order.size() && triangle_cells[order[j]] == triangle_cells[order[i]]) ++j;
            patches[triangle_cells[order[i]]] = {i, j};
            cells.push_back(triangle_cells[order[i]]);
            i = j;
        }
        std::vector<uint32_t> patch;
        auto try_cell = [&](uint64_t cell, bool neighbour) {
            const auto [begin, end] = patches.at(cell);
            patch.assign(order.begin() + long(begin), order.begin() + long(end));
            return sharpener.try_cell(cell, patch, neighbour, local);
        };
        std::vector<uint64_t> found;
        for (uint64_t cell : cells)
            if (try_cell(cell, false)) found.push_back(cell);
        // Then outwards along the features: the six neighbours of each feature cell.
        std::unordered_map<uint64_t, char> tried;
        for (uint64_t cell : found) tried[cell] = 1;
        for (std::size_t i = 0; i < found.size(); ++i)
            for (uint64_t next : sharpener.face_neighbours(found[i]))
                if (patches.count(next) && !tried[next]++ && try_cell(next, true)) found.push_back(next);
        sharpener.join_all(local);
        sharpener.finish();
    }
    if (stats) *stats = local;
}

}  // namespace fortu
