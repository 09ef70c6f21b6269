// interp/mesh_cover.cpp — surface points far from the mesh found by Newton and put in as
// vertices (the why is in mesh_cover.hpp).
#include "interp/mesh_cover.hpp"

#include "interp/lane_points.hpp"
#include "interp/parallel.hpp"
#include "interp/segment_through_triangle.hpp"
#include "interp/tape.hpp"
#include "runtime/mesh_compare.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

namespace fortu {
namespace {

using Vec = std::array<double, 3>;

/// The cells round a triangle whose vertices' normals (the field's exact gradients) are more
/// than 90° apart are probed: a cap across a blade or a tip, whose two sides face away from
/// each other, a fold, a sharp edge. A smooth part's normals differ little in a cell, and
/// its chords are marching tetrahedra's usual error. (At 26°, or round triangles longer than
/// 1.5 cells too, the probes found nothing more on the RANOK scripts; round the long ones
/// bear.vm had five times the probes.)
constexpr double kBentCosine = 0.0;
/// Newton steps at most a quarter cell (it follows the gradient to the near surface, not a
/// far zero where the slope is small), at most this many, and not farther than two cells
/// from the probe's start (that part of the surface is another probe's).
constexpr double kMaxStep = 0.25;
constexpr int kNewtonSteps = 60;
constexpr double kMaxTravel = 2.0;
/// Probes start on a half-cell lattice (the nodes and centres alone leave gaps: Tor1 at 41
/// nodes 0.67 cells), so each point of the surface has one within √3/4 of a cell; those whose
/// first-order distance to it is more than this many cells go no further (at 0.5 new_Chainik
/// at 65 nodes kept a sample 0.515 cells off; at 2, bear.vm's probes cost 3 times as much).
constexpr double kProbeReach = 0.75;
/// A probe within this many cells of the surface (to first order) is measured against the
/// mesh before it goes on.
constexpr double kFirstOrder = 0.1;
/// A new triangle's area, in cell², at least (the feature pass's bound, mesh_features.cpp).
constexpr double kMinArea = 1e-5;
/// Triangles near a far point tried for a split, nearest first (2 left Tor1 at 41 nodes 0.60
/// cells off).
constexpr int kSplitCandidates = 8;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec scale(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec& a) { return std::sqrt(dot(a, a)); }
bool finite(const Vec& a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

/// The model's values and exact gradients at a batch of points (dual numbers, a lane each:
/// the tape is read once per batch, not once per point), or its values alone.
class GradientField {
public:
    explicit GradientField(const Tape& tape) : tape_(tape) {}
    /// Evaluates at `points` (at least one); value(k) and gradient(k) read point k's.
    void at(const std::vector<Vec>& points) {
        root_ = run_at_points(tape_, lanes_, slots_, int(points.size()), [&](int k, int axis) { return points[std::size_t(k)][std::size_t(axis)]; });
    }
    double value(std::size_t k) const { return root_[k].v; }
    Vec gradient(std::size_t k) const { return {root_[k].d[0], root_[k].d[1], root_[k].d[2]}; }
    /// At one point.
    double at(const Vec& p, Vec& gradient) {
        at(std::vector<Vec>{p});
        gradient = this->gradient(0);
        return value(0);
    }
    /// The values alone at `points` (plain doubles: about a quarter of the cost), in order.
    const double* values(const std::vector<Vec>& points) {
        return run_at_points(tape_, plain_, plain_slots_, int(points.size()), [&](int k, int axis) { return points[std::size_t(k)][std::size_t(axis)]; });
    }

private:
    const Tape& tape_;
    std::vector<ir::Dual> lanes_;
    std::vector<ir::Dual*> slots_;
    const ir::Dual* root_ = nullptr;
    std::vector<double> plain_;
    std::vector<double*> plain_slots_;
};

struct FarPoint {
    Vec point;
    double distance;  ///< to the mesh when found, in model units
    bool crossing;    ///< a sharp edge's crossing, not a probe's (counted apart: CoverStats)
};

class Cover {
public:
    /// `edge_points`: points of the surface to be measured too (with a cell round each).
    Cover(const Tape& tape, const Grid& grid, Mesh& mesh, const std::vector<Vec>& edge_points) : field_(tape), mesh_(mesh) {
        const Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
        for (int a = 0; a < 3; ++a) {
            min_[a] = axes[a]->min;
            max_[a] = axes[a]->max;
            step_[a] = axes[a]->step();
            cells_[a] = axes[a]->nodes - 1;
        }
        h_ = std::max({step_[0], step_[1], step_[2]});
        // The probed cells, and round them the cells a probe may land in or measure from
        // (two cells of travel, one of reach): only triangles there are looked up.
        for (uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
            if (!bent(t)) continue;
            std::array<int64_t, 3> lo, hi;
            cell_range(t, lo, hi, 0);
            for (int64_t z = lo[2]; z <= hi[2]; ++z)
                for (int64_t y = lo[1]; y <= hi[1]; ++y)
                    for (int64_t x = lo[0]; x <= hi[0]; ++x) probed_.push_back(key({x, y, z}));
        }
        probed_ = grown(std::move(probed_), 1);
        std::vector<uint64_t> measured;
        for (const Vec& p : edge_points) measured.push_back(key(cell_of(p)));
        if (probed_.empty() && measured.empty()) return;
        region_ = grown(probed_, 3);
        measured = grown(std::move(measured), 2);
        std::vector<uint64_t> both;
        std::set_union(region_.begin(), region_.end(), measured.begin(), measured.end(), std::back_inserter(both));
        region_ = std::move(both);
        for (uint32_t t = 0; t < mesh_.triangles.size(); ++t) bucket(t);
    }

    double h() const { return h_; }
    double step(int axis) const { return step_[axis]; }

    /// The probes' starts: the 27 points of the half-cell lattice in each probed cell, in
    /// half-cell integer coordinates, sorted.
    std::vector<std::array<int64_t, 3>> probe_starts() const {
        std::vector<std::array<int64_t, 3>> starts;
        for (uint64_t cell : probed_) {
            const std::array<int64_t, 3> c = coords(cell);
            for (int k = 0; k < 27; ++k) starts.push_back({2 * c[0] + k % 3, 2 * c[1] + k / 3 % 3, 2 * c[2] + k / 9});
        }
        std::sort(starts.begin(), starts.end());
        starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
        return starts;
    }

    Vec position(const std::array<int64_t, 3>& half) const {
        return {min_[0] + double(half[0]) * step_[0] / 2, min_[1] + double(half[1]) * step_[1] / 2,
                min_[2] + double(half[2]) * step_[2] / 2};
    }

    /// Newton from each of `points` onto the boundary of the solid (where the field changes
    /// sign), at most `travel` from where it starts; none where it does not converge. The
    /// points go on together, a batch of lanes. With `covered`, a point stops as soon as
    /// covered(p, r) says the surface within r of p (to first order) is near the mesh: most
    /// probes land where the mesh is, and two steps tell.
    template <class Covered>
    static std::vector<std::optional<Vec>> project(GradientField& field, std::vector<Vec> points, double h, double reach,
                                                   double travel, Covered&& covered) {
        std::vector<std::optional<Vec>> out(points.size());
        const std::vector<Vec> start = points;
        // Across a crease (an acute convex edge: Tor1's twisted square, 25° at its inner side,
        // a blade's edge; or a concave one) each Newton step lands on the other face's side,
        // whose gradient points nearly the other way: alone the steps zigzag towards the edge
        // a little each time, or not at all. So each point keeps where it was last on the other
        // side, and steps onto both faces' tangent planes at once (the nearest point of their
        // line): on the edge in a few steps. There each gradient points out of the other
        // face's inside; only their bisector points into the solid.
        struct Sample {
            Vec point;
            double value = 0;
            Vec gradient{};  ///< zero: none yet
        };
        std::vector<Sample> last(points.size()), other(points.size());
        std::vector<std::size_t> active(points.size()), landed;
        for (std::size_t k = 0; k < active.size(); ++k) active[k] = k;
        std::vector<Vec> at;
        for (int i = 0; i < kNewtonSteps && !active.empty(); ++i) {
            at.clear();
            for (std::size_t k : active) at.push_back(points[k]);
            field.at(at);
            std::vector<std::size_t> next;
            for (std::size_t j = 0; j < active.size(); ++j) {
                const std::size_t k = active[j];
                const double v = field.value(j);
                const Vec g = field.gradient(j);
                const double g2 = dot(g, g);
                if (!std::isfinite(v) || !(g2 > 0) || !std::isfinite(g2)) continue;
                const double length = std::fabs(v) / std::sqrt(g2);
                if (i == 0 && length > reach) continue;
                if (length < kFirstOrder * h && covered(points[k], length)) continue;
                if (dot(g, last[k].gradient) < 0) other[k] = last[k];
                last[k] = {points[k], v, g};
                Vec step = scale(g, -v / g2);
                const Vec& q = other[k].gradient;
                const double across = dot(g, q), q2 = dot(q, q), det = g2 * q2 - across * across;
                if (across < 0 && det > 1e-6 * g2 * q2) {
                    // The other face's plane through its last point, at this point: q·d = −w.
                    const double w = other[k].value + dot(q, sub(points[k], other[k].point));
                    step = add(scale(g, (-v * q2 + w * across) / det), scale(q, (-w * g2 + v * across) / det));
                }
                const double stride = norm(step);
                if (stride > kMaxStep * h) step = scale(step, kMaxStep * h / stride);
                points[k] = add(points[k], step);
                if (!finite(points[k]) || norm(sub(points[k], start[k])) > travel) continue;
                if (length < 1e-9 * h && stride < 1e-9 * h) {
                    landed.push_back(k);
                } else {
                    next.push_back(k);
                }
            }
            active = std::move(next);
        }
        // On the boundary: both signs within a millionth of a cell along the gradient or the
        // bisector of it and the other side's (not a zero the field only touches).
        at.clear();
        for (std::size_t k : landed) {
            const Vec n = scale(last[k].gradient, 1 / norm(last[k].gradient));
            const Vec& q = other[k].gradient;
            const Vec sum = dot(q, q) > 0 ? add(n, scale(q, 1 / norm(q))) : n;
            const Vec bisector = norm(sum) > 1e-3 ? scale(sum, 1 / norm(sum)) : n;
            for (const Vec& d : {scale(n, 1e-6 * h), scale(bisector, 1e-6 * h)}) at.push_back(add(points[k], d)), at.push_back(sub(points[k], d));
        }
        if (!landed.empty()) field.at(at);
        for (std::size_t j = 0; j < landed.size(); ++j) {
            int positive = 0;
            for (std::size_t e = 0; e < 4; ++e) positive += field.value(4 * j + e) > 0;
            if (positive % 4 != 0) out[landed[j]] = points[landed[j]];
        }
        return out;
    }

    /// Whether p is at least 1.5 cells inside the domain (the mesh closes a solid the domain
    /// cuts on its outer nodes, which is not the surface).
    bool interior(const Vec& p) const {
        for (int a = 0; a < 3; ++a)
            if (p[a] < min_[a] + 1.5 * step_[a] || p[a] > max_[a] - 1.5 * step_[a]) return false;
        return true;
    }

    /// The distance from p to the mesh, if a triangle is within a cell of it; else infinity.
    /// With `enough`, any distance below it may be returned as soon as one is found (p's own
    /// cell first).
    double distance(const Vec& p, double enough = 0) const {
        double best = INFINITY;
        for_each_near(
            p, [&] { return best; },
            [&](uint32_t, double d) {
                best = std::min(best, d);
                return best >= enough;
            });
        return best;
    }

    /// Puts p into the mesh by splitting a triangle near it into three round it; false when no
    /// split is valid. (Not an edge with the triangle across it: that never helped on the
    /// RANOK scripts, and it would take a sharp feature's mesh edge off the mesh.)
    bool insert(const Vec& p) {
        std::vector<std::pair<double, uint32_t>> near;
        for_each_near(
            p, [] { return INFINITY; },
            [&](uint32_t t, double d) {
                near.push_back({d, t});
                return true;
            });
        std::sort(near.begin(), near.end());
        near.erase(std::unique(near.begin(), near.end()), near.end());
        near.resize(std::min<std::size_t>(near.size(), kSplitCandidates));
        Vec normal;
        field_.at(p, normal);
        normal = scale(normal, -1 / norm(normal));  // outward
        for (const auto& [distance, t] : near)
            if (split_face(t, p, normal)) return true;
        return false;
    }

private:
    uint64_t key(const std::array<int64_t, 3>& c) const {
        return uint64_t(c[0]) + uint64_t(cells_[0]) * (uint64_t(c[1]) + uint64_t(cells_[1]) * uint64_t(c[2]));
    }
    std::array<int64_t, 3> coords(uint64_t cell) const {
        return {int64_t(cell % uint64_t(cells_[0])), int64_t(cell / uint64_t(cells_[0]) % uint64_t(cells_[1])),
                int64_t(cell / (uint64_t(cells_[0]) * uint64_t(cells_[1])))};
    }
    bool inside_lattice(const std::array<int64_t, 3>& c) const {
        for (int a = 0; a < 3; ++a)
            if (c[a] < 0 || c[a] >= cells_[a]) return false;
        return true;
    }
    int64_t axis_cell(double v, int a) const {
        const double f = std::floor((v - min_[a]) / step_[a]);
        return std::clamp<int64_t>(std::isfinite(f) ? int64_t(std::clamp(f, -1.0, double(cells_[a]))) : 0, 0, cells_[a] - 1);
    }
    std::array<int64_t, 3> cell_of(const Vec& p) const { return {axis_cell(p[0], 0), axis_cell(p[1], 1), axis_cell(p[2], 2)}; }

    /// The cells triangle t's bounding box meets, grown by `grow` cells, clamped to the lattice.
    void cell_range(uint32_t t, std::array<int64_t, 3>& lo, std::array<int64_t, 3>& hi, int grow) const {
        const auto& tri = mesh_.triangles[t];
        for (int a = 0; a < 3; ++a) {
            double l = INFINITY, u = -INFINITY;
            for (uint32_t v : tri) l = std::min(l, mesh_.vertices[v][a]), u = std::max(u, mesh_.vertices[v][a]);
            lo[a] = std::max<int64_t>(axis_cell(l, a) - grow, 0);
            hi[a] = std::min<int64_t>(axis_cell(u, a) + grow, cells_[a] - 1);
        }
    }
    /// Calls visit(t, distance from p) for the triangles filed in p's cell (first) and the 26
    /// round it whose bounding box is nearer than bound() (a triangle filed in several cells
    /// comes again), until visit returns false.
    template <class Bound, class Visit>
    void for_each_near(const Vec& p, Bound&& bound, Visit&& visit) const {
        const std::array<int64_t, 3> c = cell_of(p);
        for (int k = 0; k < 27; ++k) {
            const int o = k == 0 ? 13 : k <= 13 ? k - 1 : k;
            const std::array<int64_t, 3> at{c[0] + o % 3 - 1, c[1] + o / 3 % 3 - 1, c[2] + o / 9 - 1};
            if (!inside_lattice(at)) continue;
            const auto it = buckets_.find(key(at));
            if (it == buckets_.end()) continue;
            for (uint32_t t : it->second) {
                const auto& tri = mesh_.triangles[t];
                const Vec& a = mesh_.vertices[tri[0]];
                const Vec& b = mesh_.vertices[tri[1]];
                const Vec& e = mesh_.vertices[tri[2]];
                double box2 = 0;  // squared distance from p to the triangle's bounding box
                for (int i = 0; i < 3; ++i) {
                    const double gap = std::max({std::min({a[i], b[i], e[i]}) - p[i], p[i] - std::max({a[i], b[i], e[i]}), 0.0});
                    box2 += gap * gap;
                }
                const double limit = bound();
                if (box2 >= limit * limit) continue;
                if (!visit(t, point_triangle_distance(p, a, b, e))) return;
            }
        }
    }
    /// The cells within `by` cells of `cells` along each axis (a cube round each), sorted;
    /// grown one axis at a time, so each cell is written 3·(2·by + 1) times, not (2·by + 1)³.
    std::vector<uint64_t> grown(std::vector<uint64_t> cells, int by) const {
        std::sort(cells.begin(), cells.end());
        cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
        for (int axis = 0; axis < 3; ++axis) {
            std::vector<uint64_t> next;
            next.reserve(cells.size() * std::size_t(2 * by + 1));
            for (uint64_t cell : cells) {
                std::array<int64_t, 3> c = coords(cell);
                const int64_t at = c[std::size_t(axis)];
                for (int64_t d = std::max<int64_t>(at - by, 0); d <= std::min<int64_t>(at + by, cells_[axis] - 1); ++d) {
                    c[std::size_t(axis)] = d;
                    next.push_back(key(c));
                }
            }
            std::sort(next.begin(), next.end());
            next.erase(std::unique(next.begin(), next.end()), next.end());
            cells = std::move(next);
        }
        return cells;
    }
    bool in_region(uint64_t cell) const { return std::binary_search(region_.begin(), region_.end(), cell); }
    /// Files triangle t under the cells of the region its bounding box meets.
    void bucket(uint32_t t) {
        std::array<int64_t, 3> lo, hi;
        cell_range(t, lo, hi, 0);
        for (int64_t z = lo[2]; z <= hi[2]; ++z)
            for (int64_t y = lo[1]; y <= hi[1]; ++y)
                for (int64_t x = lo[0]; x <= hi[0]; ++x) {
                    const uint64_t cell = key({x, y, z});
                    if (!in_region(cell)) continue;
                    auto& list = buckets_[cell];
                    if (list.empty() || list.back() != t) list.push_back(t);
                }
    }
    Vec face_normal(const std::array<uint32_t, 3>& tri) const {
        return cross(sub(mesh_.vertices[tri[1]], mesh_.vertices[tri[0]]), sub(mesh_.vertices[tri[2]], mesh_.vertices[tri[0]]));
    }

    /// Whether two of triangle t's vertex normals (the field's exact gradients) are more than
    /// the bend apart, away from the domain's faces; a normal that is not finite, at a
    /// feature's vertex, is left out. Not its face normal: a sliver's is anything (tanglecube.vm's
    /// smooth surface has them).
    bool bent(uint32_t t) const {
        if (mesh_.normals.size() != mesh_.vertices.size()) return false;
        const auto& tri = mesh_.triangles[t];
        for (uint32_t v : tri)
            if (!interior(mesh_.vertices[v])) return false;  // the domain's cap and the cells beside it
        for (int i = 0; i < 3; ++i)
            for (int j = i + 1; j < 3; ++j) {
                const Vec& m = mesh_.normals[tri[std::size_t(i)]];
                const Vec& n = mesh_.normals[tri[std::size_t(j)]];
                if (finite(m) && finite(n) && dot(m, n) < kBentCosine) return true;
            }
        return false;
    }

    /// Whether a point of the surface is within `reach` of each of `points`: the one Newton
    /// finds from it (its distance bounds the nearest's). All in one batch of lanes, the tape
    /// read once a step for all (one at a time, bear.vm at 257 nodes spent 0.45 s here, serial).
    bool near_surface(const std::vector<Vec>& points, double reach) {
        const std::vector<std::optional<Vec>> landed =
            project(field_, points, h_, reach, reach + kMaxStep * h_, [](const Vec&, double) { return false; });
        for (std::size_t k = 0; k < points.size(); ++k)
            if (!landed[k] || !(norm(sub(*landed[k], points[k])) <= reach)) return false;
        return true;
    }

    /// Whether the triangles `fresh` may replace those numbered `old`: each not degenerate,
    /// within the region whose triangles are filed, crossing no other triangle, and within
    /// kCoverDistance of the surface at its centroid and edge midpoints. (Not that it faces
    /// the way its vertices' normals do: a tent over a tip's cap, whose vertices face sideways,
    /// often does not, and Chainik's tips at 41 nodes were left 0.6 cells off so.)
    bool valid(const std::vector<std::array<uint32_t, 3>>& fresh, const std::vector<uint32_t>& old) {
        for (const auto& tri : fresh)
            if (!(norm(face_normal(tri)) / 2 >= kMinArea * h_ * h_)) return false;
        // Crossings with the triangles round them, not those replaced.
        const double eps = 1e-12 * h_ * h_ * h_;
        for (const auto& tri : fresh) {
            std::array<int64_t, 3> lo{}, hi{};
            for (int a = 0; a < 3; ++a) {
                double l = INFINITY, u = -INFINITY;
                for (uint32_t v : tri) l = std::min(l, mesh_.vertices[v][a]), u = std::max(u, mesh_.vertices[v][a]);
                lo[a] = axis_cell(l, a);
                hi[a] = axis_cell(u, a);
            }
            std::vector<uint32_t> seen;
            for (int64_t z = lo[2]; z <= hi[2]; ++z)
                for (int64_t y = lo[1]; y <= hi[1]; ++y)
                    for (int64_t x = lo[0]; x <= hi[0]; ++x) {
                        if (!in_region(key({x, y, z}))) return false;  // its neighbours there are not filed
                        const auto it = buckets_.find(key({x, y, z}));
                        if (it != buckets_.end()) seen.insert(seen.end(), it->second.begin(), it->second.end());
                    }
            std::sort(seen.begin(), seen.end());
            seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
            for (uint32_t t : seen) {
                if (std::find(old.begin(), old.end(), t) != old.end()) continue;
                if (crosses(tri, mesh_.triangles[t], eps)) return false;
            }
        }
        // Last, as it costs a Newton projection per point: all of them together, each edge
        // midpoint once (a split's three triangles share their spokes).
        std::vector<Vec> points;
        for (const auto& tri : fresh) {
            const Vec& a = mesh_.vertices[tri[0]];
            const Vec& b = mesh_.vertices[tri[1]];
            const Vec& c = mesh_.vertices[tri[2]];
            for (const Vec& x : {scale(add(add(a, b), c), 1.0 / 3), scale(add(a, b), 0.5), scale(add(b, c), 0.5), scale(add(c, a), 0.5)})
                if (std::find(points.begin(), points.end(), x) == points.end()) points.push_back(x);
        }
        return near_surface(points, kCoverDistance * h_);
    }

    /// Whether triangles s and t meet other than in the vertices or edge they share.
    bool crosses(const std::array<uint32_t, 3>& s, const std::array<uint32_t, 3>& t, double eps) const {
        auto at = [&](uint32_t v) -> const Vec& { return mesh_.vertices[v]; };
        int shared = 0;
        for (uint32_t v : s) shared += std::count(t.begin(), t.end(), v) > 0;
        if (shared == 3) return true;
        if (shared == 2) {  // folded onto each other across their edge
            const Vec n = face_normal(s), m = face_normal(t);
            return dot(n, m) < -0.999 * norm(n) * norm(m);
        }
        for (int e = 0; e < 3; ++e) {
            const uint32_t p = s[std::size_t(e)], q = s[std::size_t((e + 1) % 3)];
            if (shared == 1 && (std::count(t.begin(), t.end(), p) || std::count(t.begin(), t.end(), q))) continue;
            if (segment_through_triangle(at(p), at(q), at(t[0]), at(t[1]), at(t[2]), eps, EndOnPlane::crosses)) return true;
        }
        for (int e = 0; e < 3; ++e) {
            const uint32_t p = t[std::size_t(e)], q = t[std::size_t((e + 1) % 3)];
            if (shared == 1 && (std::count(s.begin(), s.end(), p) || std::count(s.begin(), s.end(), q))) continue;
            if (segment_through_triangle(at(p), at(q), at(s[0]), at(s[1]), at(s[2]), eps, EndOnPlane::crosses)) return true;
        }
        return false;
    }

    uint32_t add_vertex(const Vec& p, const Vec& normal) {
        mesh_.vertices.push_back(p);
        if (mesh_.normals.size() + 1 == mesh_.vertices.size()) mesh_.normals.push_back(normal);
        return uint32_t(mesh_.vertices.size() - 1);
    }
    void drop_vertex() {
        mesh_.vertices.pop_back();
        if (mesh_.normals.size() > mesh_.vertices.size()) mesh_.normals.pop_back();
    }

    /// Replaces the triangles numbered `old` by `fresh` (as many or more), if valid.
    bool replace(const std::vector<uint32_t>& old, const std::vector<std::array<uint32_t, 3>>& fresh) {
        if (!valid(fresh, old)) return false;
        for (std::size_t i = 0; i < fresh.size(); ++i) {
            uint32_t t;
            if (i < old.size()) {
                t = old[i];
                mesh_.triangles[t] = fresh[i];
            } else {
                t = uint32_t(mesh_.triangles.size());
                mesh_.triangles.push_back(fresh[i]);
            }
            bucket(t);
        }
        return true;
    }

    bool split_face(uint32_t t, const Vec& p, const Vec& normal) {
        const auto [a, b, c] = mesh_.triangles[t];
        const uint32_t v = add_vertex(p, normal);
        if (replace({t}, {{a, b, v}, {b, c, v}, {c, a, v}})) return true;
        drop_vertex();
        return false;
    }

    GradientField field_;
    Mesh& mesh_;
    double min_[3], max_[3], step_[3];
    int64_t cells_[3];
    double h_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> buckets_;  ///< cell → triangles whose box meets it
    std::vector<uint64_t> probed_;                                 ///< the cells probed, sorted
    std::vector<uint64_t> region_;  ///< they and the cells within 3 of them (2 of an edge point's), sorted: where triangles are filed
};

}  // namespace

void cover_surface(const ir::Graph& graph, ir::NodeId root, const Grid& grid, Mesh& mesh, const EvalOptions& options,
                   const std::vector<std::array<double, 3>>& edge_points, CoverStats* stats) {
    CoverStats local;
    CoverStats& s = stats ? *stats : local;
    if (mesh.triangles.empty() || grid.dims != 3) return;
    const Tape tape = compile_tape(graph, TapeSpec{{root}, {}, {}, true});
    Cover cover(tape, grid, mesh, edge_points);
    const double h = cover.h();
    std::vector<std::array<int64_t, 3>> starts = cover.probe_starts();
    const int workers = worker_count(starts.size(), options);
    std::vector<GradientField> fields;
    for (int w = 0; w < std::max(workers, 1); ++w) fields.emplace_back(tape);
    constexpr std::size_t kChunk = 64;
    // First the values alone on the probes' half-cell lattice: where they say the surface is
    // farther than kProbeReach (|f| over the steepest one-sided differences, which the slope
    // exceeds little), the start is left out before Newton needs the gradient there.
    {
        std::vector<double> value(starts.size());
        parallel_ranges(starts.size(), kChunk, options, [&](std::size_t begin, std::size_t end, int worker) {
            std::vector<Vec> points;
            for (std::size_t i = begin; i < end; ++i) points.push_back(cover.position(starts[i]));
            const double* v = fields[std::size_t(worker)].values(points);
            std::copy(v, v + points.size(), value.begin() + long(begin));
        });
        if (options.cancel && options.cancel->load()) return;
        // Each start's test reads only the values, so the starts are shared among the threads.
        const auto near_enough = [&](std::size_t i) {
            double slope2 = 0;
            bool known = std::isfinite(value[i]);
            for (int a = 0; a < 3 && known; ++a) {
                double steepest = -1;
                for (int side : {-1, 1}) {
                    std::array<int64_t, 3> q = starts[i];
                    q[std::size_t(a)] += side;
                    const auto it = std::lower_bound(starts.begin(), starts.end(), q);
                    if (it == starts.end() || *it != q) continue;
                    const double other = value[std::size_t(it - starts.begin())];
                    if (std::isfinite(other)) steepest = std::max(steepest, std::fabs(other - value[i]) / (cover.step(a) / 2));
                }
                known = steepest >= 0;
                slope2 += steepest * steepest;
            }
            return !known || !(std::fabs(value[i]) > kProbeReach * h * std::sqrt(slope2));
        };
        std::vector<char> keep(starts.size());
        parallel_ranges(starts.size(), kChunk, options, [&](std::size_t begin, std::size_t end, int) {
            for (std::size_t i = begin; i < end; ++i) keep[i] = near_enough(i);
        });
        std::vector<std::array<int64_t, 3>> near;
        for (std::size_t i = 0; i < starts.size(); ++i)
            if (keep[i]) near.push_back(starts[i]);
        starts = std::move(near);
    }
    s.probes = starts.size();
    // Projections and their distances to the mesh in parallel (each worker its own
    // evaluator), the far ones gathered after, in order.
    std::vector<std::optional<Vec>> projected(starts.size());
    std::vector<double> to_mesh(starts.size());
    parallel_ranges(starts.size(), kChunk, options, [&](std::size_t begin, std::size_t end, int worker) {
        std::vector<Vec> points;
        for (std::size_t i = begin; i < end; ++i) points.push_back(cover.position(starts[i]));
        auto landed = Cover::project(fields[std::size_t(worker)], points, h, kProbeReach * h, kMaxTravel * h, [&](const Vec& p, double r) {
            const double enough = kCoverDistance * h - 2 * r;
            return cover.distance(p, enough) < enough;
        });
        for (std::size_t k = 0; k < landed.size(); ++k)
            if (landed[k] && cover.interior(*landed[k])) to_mesh[begin + k] = cover.distance(*landed[k]);
        std::move(landed.begin(), landed.end(), projected.begin() + long(begin));
    });
    if (options.cancel && options.cancel->load()) return;
    std::vector<FarPoint> far;
    for (std::size_t i = 0; i < projected.size(); ++i)
        if (projected[i] && cover.interior(*projected[i]) && to_mesh[i] > kCoverDistance * h) far.push_back({*projected[i], to_mesh[i], false});
    s.far = far.size();
    // The sharp edges' crossings the feature pass could not make vertices: points of the
    // surface already, put in as the probes' are (and counted on the finished mesh below).
    for (const Vec& p : edge_points) {
        if (!cover.interior(p)) continue;
        const double d = cover.distance(p);
        if (d > kCoverDistance * h) far.push_back({p, d, true});
    }
    // Farthest first; each measured again, as an earlier one's vertex may cover it.
    std::sort(far.begin(), far.end(), [](const FarPoint& a, const FarPoint& b) {
        return a.distance != b.distance ? a.distance > b.distance : a.point < b.point;
    });
    std::vector<Vec> refused;
    for (const FarPoint& f : far) {
        const double d = cover.distance(f.point);
        if (!(d > kCoverDistance * h)) {
            s.covered += !f.crossing;
        } else if (cover.insert(f.point)) {
            s.inserted += !f.crossing;
        } else if (!f.crossing) {
            refused.push_back(f.point);
        }
    }
    // Those refused measured again at the end: a nearer point's vertex, put in after, may
    // cover one (new_Chainik at 64 nodes, far at 0.3 cells: 20 refused, the farthest 0.957
    // cells when refused; 15 left at the end, the farthest 0.437).
    for (const Vec& p : refused) {
        const double d = cover.distance(p);
        if (!(d > kCoverDistance * h)) {
            ++s.covered;
            continue;
        }
        ++s.refused;
        if (std::isfinite(d)) s.farthest_left = std::max(s.farthest_left, d / h);  // else no triangle within a cell
    }
    // The edges' crossings on the finished mesh: within a billionth of a cell is on it.
    for (const Vec& p : edge_points) {
        const double d = cover.distance(p);
        if (d <= 1e-9 * h) continue;
        ++s.crossings_off_mesh;
        s.farthest_crossing_off = std::max(s.farthest_crossing_off, d / h);
    }
}

}  // namespace fortu
