// tests/unit/mesh_checker.hpp — an independent check of a mesh file fortu wrote: its own
// STL/PLY readers (not runtime/mesh_io), its own topology, orientation, degeneracy and
// self-intersection tests, and distances to the true surface measured on the model's field
// (the point evaluator, not the mesher): by Newton projection, and where Newton cannot reach
// the surface (a field that jumps, an edge without a gradient) by where the field changes
// sign. Shares no code with the mesher.
#pragma once

#include "interp/voxel_engine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace fortu::test {

using P3 = std::array<double, 3>;

struct CheckedMesh {
    std::vector<P3> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;
};

inline std::string file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Binary STL, vertices welded by their exact float32 coordinates.
inline CheckedMesh read_binary_stl(const std::string& path) {
    const std::string b = file_bytes(path);
    if (b.size() < 84) throw std::runtime_error("short STL");
    uint32_t n;
    std::memcpy(&n, b.data() + 80, 4);
    if (b.size() != 84 + std::size_t(n) * 50) throw std::runtime_error("STL size does not match its count");
    CheckedMesh m;
    std::map<std::array<float, 3>, uint32_t> index;
    for (uint32_t t = 0; t < n; ++t) {
        std::array<uint32_t, 3> tri{};
        for (int k = 0; k < 3; ++k) {
            std::array<float, 3> f;
            std::memcpy(f.data(), b.data() + 84 + std::size_t(t) * 50 + 12 + 12 * k, 12);
            auto [it, fresh] = index.emplace(f, uint32_t(m.vertices.size()));
            if (fresh) m.vertices.push_back({f[0], f[1], f[2]});
            tri[k] = it->second;
        }
        m.triangles.push_back(tri);
    }
    return m;
}

/// Binary little-endian PLY with double x y z (and any further double vertex properties).
inline CheckedMesh read_binary_ply(const std::string& path) {
    const std::string b = file_bytes(path);
    const std::size_t end = b.find("end_header\n");
    if (end == std::string::npos) throw std::runtime_error("no PLY header");
    std::istringstream h(b.substr(0, end));
    std::string line, element;
    std::size_t nv = 0, nf = 0, props = 0;
    while (std::getline(h, line)) {
        std::istringstream w(line);
        std::string k;
        w >> k;
        if (k == "element") {
            std::size_t count;
            w >> element >> count;
            (element == "vertex" ? nv : nf) = count;
        } else if (k == "property" && element == "vertex") {
            ++props;
        }
    }
    CheckedMesh m;
    std::size_t at = end + 11;
    for (std::size_t v = 0; v < nv; ++v, at += 8 * props) {
        P3 p;
        std::memcpy(p.data(), b.data() + at, 24);
        m.vertices.push_back(p);
    }
    for (std::size_t f = 0; f < nf; ++f) {
        if (uint8_t(b[at]) != 3) throw std::runtime_error("non-triangle face");
        std::array<uint32_t, 3> t;
        std::memcpy(t.data(), b.data() + at + 1, 12);
        at += 13;
        m.triangles.push_back(t);
    }
    if (at != b.size()) throw std::runtime_error("PLY size does not match its header");
    return m;
}

inline P3 minus(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline P3 cross(const P3& a, const P3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double dot3(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline double orient(const P3& a, const P3& b, const P3& c, const P3& d) {
    return dot3(minus(b, a), cross(minus(c, a), minus(d, a)));
}

/// The sign of orient(), 0 within round-off: `scale` is a length of the configuration, and
/// volumes below 1e-9 of scale³ count as flat (coplanar triangles are not tested for overlap).
inline int orient_sign(const P3& a, const P3& b, const P3& c, const P3& d, double scale) {
    const double v = orient(a, b, c, d);
    const double eps = 1e-9 * scale * scale * scale;
    return v > eps ? 1 : v < -eps ? -1 : 0;
}

/// Whether segment pq crosses the interior of triangle abc (strictly; touching is not crossing).
inline bool segment_crosses(const P3& p, const P3& q, const P3& a, const P3& b, const P3& c, double scale) {
    const int s1 = orient_sign(a, b, c, p, scale), s2 = orient_sign(a, b, c, q, scale);
    if (s1 * s2 != -1) return false;
    const int u = orient_sign(p, q, a, b, scale), v = orient_sign(p, q, b, c, scale), w = orient_sign(p, q, c, a, scale);
    return (u > 0 && v > 0 && w > 0) || (u < 0 && v < 0 && w < 0);
}

/// Distance from p to triangle abc (by projection and the three edges).
inline double distance_to_triangle(const P3& p, const P3& a, const P3& b, const P3& c) {
    const P3 n = cross(minus(b, a), minus(c, a));
    const double nn = dot3(n, n);
    if (nn > 0) {
        const double d = dot3(minus(p, a), n) / nn;
        const P3 f{p[0] - d * n[0], p[1] - d * n[1], p[2] - d * n[2]};
        if (dot3(cross(minus(b, a), minus(f, a)), n) >= 0 && dot3(cross(minus(c, b), minus(f, b)), n) >= 0 &&
            dot3(cross(minus(a, c), minus(f, c)), n) >= 0)
            return std::fabs(d) * std::sqrt(nn);
    }
    auto seg = [&](const P3& s, const P3& e) {
        const P3 d = minus(e, s);
        const double t = std::clamp(dot3(minus(p, s), d) / std::max(dot3(d, d), 1e-300), 0.0, 1.0);
        const P3 x{s[0] + t * d[0] - p[0], s[1] + t * d[1] - p[1], s[2] + t * d[2] - p[2]};
        return std::sqrt(dot3(x, x));
    };
    return std::min({seg(a, b), seg(b, c), seg(c, a)});
}

struct MeshCheck {
    std::size_t triangles = 0;
    std::size_t open_edges = 0, overused_edges = 0, same_direction_edges = 0;
    std::size_t degenerate = 0;          ///< area below 1e-10 cell²
    std::size_t intersecting_pairs = 0;
    double signed_volume = 0;
    std::size_t normals_checked = 0, normals_wrong = 0;  ///< the field does not decrease along the normal (centroid ± cell/8)
    double mesh_to_surface = 0;          ///< max over vertices and centroids
    double surface_to_mesh = 0;          ///< max over samples of the solid's boundary
    std::size_t samples = 0;
    P3 worst_mesh_point{}, worst_surface_point{};  ///< where each maximum is
};

/// "(x, y, z) and (x, y, z)": where the two distances are largest, for a failing check's message.
inline std::string worst_points(const MeshCheck& r) {
    std::ostringstream out;
    out << "(" << r.worst_mesh_point[0] << ", " << r.worst_mesh_point[1] << ", " << r.worst_mesh_point[2] << ") and ("
        << r.worst_surface_point[0] << ", " << r.worst_surface_point[1] << ", " << r.worst_surface_point[2] << ")";
    return out.str();
}

/// Whether p is inside the solid: f > 0. A zero or a NaN counts as outside, as the mesher's
/// nodes do (a NaN where SQRT's argument is negative ends the solid; one only on a plane or a
/// line, 0/0, the mesher reads beside it, and samples never fall on it).
inline bool inside(const PointEvaluator& f, const P3& p) { return f(p).value > 0; }

/// An upper bound on the distance from p to the solid's boundary (a point every neighbourhood
/// of which holds points inside and outside), or `reach` if none is found within it: the least
/// radius r (1e-9, 1e-6 and 1e-3 of h, then steps of h/64) at which p and p + r·u, or p − r·u
/// and p + r·u, are on two sides, u along the axes and the face and body diagonals. It needs
/// no gradient and no zero, so it measures where Newton cannot: a face where the field jumps
/// (ABS(X)/X changes sign at X = 0 without passing zero), where it becomes NaN, and an edge
/// where the gradient is undefined.
inline double boundary_within(const PointEvaluator& f, const P3& p, double h, double reach) {
    static const std::vector<P3> directions = [] {
        std::vector<P3> u;
        for (int x = -1; x <= 1; ++x)
            for (int y = -1; y <= 1; ++y)
                for (int z = 0; z <= 1; ++z) {
                    if (z == 0 && (y < 0 || (y == 0 && x <= 0))) continue;  // one of each ± pair
                    const double n = std::sqrt(double(x * x + y * y + z * z));
                    u.push_back({x / n, y / n, z / n});
                }
        return u;
    }();
    const bool here = inside(f, p);
    auto apart_at = [&](double r) {
        for (const P3& u : directions) {
            const bool a = inside(f, {p[0] + r * u[0], p[1] + r * u[1], p[2] + r * u[2]});
            const bool b = inside(f, {p[0] - r * u[0], p[1] - r * u[1], p[2] - r * u[2]});
            if (a != here || b != here) return true;
        }
        return false;
    };
    for (double r : {1e-9 * h, 1e-6 * h, 1e-3 * h})
        if (r < reach && apart_at(r)) return r;
    for (int k = 1; k * h / 64 < reach; ++k)
        if (apart_at(k * h / 64)) return k * h / 64;
    return reach;
}

/// Newton projection onto f = 0 along the gradient, each step at most `max_step` long (so it
/// follows the gradient to a near zero instead of jumping to a far one where |∇f| is small);
/// false if it does not converge.
inline bool project(const PointEvaluator& f, P3& p, double tolerance, double max_step) {
    for (int i = 0; i < 400; ++i) {
        const PointValue v = f(p);
        const double g2 = dot3(v.gradient, v.gradient);
        if (!std::isfinite(v.value) || !(g2 > 0) || !std::isfinite(g2)) return false;
        double step = v.value / g2;
        const double length = std::fabs(step) * std::sqrt(g2);
        if (length > max_step) step *= max_step / length;
        for (int k = 0; k < 3; ++k) p[k] -= step * v.gradient[k];
        if (std::fabs(v.value) / std::sqrt(g2) < tolerance) return true;
    }
    return false;
}

/// Whether a zero Newton found is on the solid's boundary: the field has both signs within
/// 1e-6 of a cell along its gradient (not a zero it only touches, as |x| at x = 0).
inline bool on_boundary(const PointEvaluator& f, const P3& p, double h) {
    const PointValue v = f(p);
    const double g = std::sqrt(dot3(v.gradient, v.gradient));
    if (!(g > 0) || !std::isfinite(g)) return false;
    const double e = 1e-6 * h / g;
    return inside(f, {p[0] + e * v.gradient[0], p[1] + e * v.gradient[1], p[2] + e * v.gradient[2]}) !=
           inside(f, {p[0] - e * v.gradient[0], p[1] - e * v.gradient[1], p[2] - e * v.gradient[2]});
}

/// Checks `m` against the field `f` on the box [lo, hi] with cell size `h`. Points within
/// 1.5 cells of the box's faces are left out of the distance checks (a solid the domain cuts
/// is closed there). The surface is sampled from a lattice of `samples` + 1 points per axis;
/// `far`, if given, receives every surface sample more than half a cell from the mesh, with
/// its distance.
inline MeshCheck check_mesh(const CheckedMesh& m, const PointEvaluator& f, const P3& lo, const P3& hi, double h,
                            int samples = 12, std::vector<std::pair<P3, double>>* far = nullptr) {
    MeshCheck r;
    r.triangles = m.triangles.size();
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    for (const auto& [e, n] : directed) {
        if (n > 1) ++r.same_direction_edges;
        const auto back = directed.find({e.second, e.first});
        if (back == directed.end()) ++r.open_edges;
        else if (back->second + n > 2) ++r.overused_edges;
    }
    const P3 origin = lo;
    auto interior = [&](const P3& p) {
        for (int k = 0; k < 3; ++k)
            if (p[k] < lo[k] + 1.5 * h || p[k] > hi[k] - 1.5 * h) return false;
        return true;
    };
    for (const auto& t : m.triangles) {
        const P3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        const P3 n = cross(minus(b, a), minus(c, a));
        const double area = std::sqrt(dot3(n, n)) / 2;
        if (!(area > 1e-10 * h * h)) ++r.degenerate;
        r.signed_volume += orient(origin, a, b, c) / 6;
        P3 g{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3};
        if (interior(g) && area > 1e-3 * h * h) {
            const double len = std::sqrt(dot3(n, n));
            const double e = h / 8;
            const P3 out{g[0] + e * n[0] / len, g[1] + e * n[1] / len, g[2] + e * n[2] / len};
            const P3 in{g[0] - e * n[0] / len, g[1] - e * n[1] / len, g[2] - e * n[2] / len};
            ++r.normals_checked;
            if (!(f(out).value < f(in).value)) ++r.normals_wrong;
        }
        for (const P3& p0 : {a, g}) {
            if (!interior(p0)) continue;
            // Newton's distance where it reaches the boundary; where it does not, or the
            // boundary may be nearer another way (a face where the field jumps), the sign
            // test, out to a cell (a point farther counts as a cell off).
            P3 p = p0;
            double d = h;
            if (project(f, p, 1e-12 * h, h / 16) && on_boundary(f, p, h)) d = std::sqrt(dot3(minus(p, p0), minus(p, p0)));
            if (d > h / 4) d = boundary_within(f, p0, h, d);
            if (d > r.mesh_to_surface) r.mesh_to_surface = d, r.worst_mesh_point = p0;
        }
    }
    // Self-intersections: triangles bucketed by their bounding boxes in cells of h.
    std::unordered_map<int64_t, std::vector<uint32_t>> buckets;
    auto cell = [&](double x, int k) { return int64_t(std::floor((x - lo[k]) / h)); };
    auto key = [](int64_t x, int64_t y, int64_t z) { return (x << 42) ^ (y << 21) ^ z; };
    for (uint32_t i = 0; i < m.triangles.size(); ++i) {
        int64_t a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            double l = 1e300, u = -1e300;
            for (uint32_t v : m.triangles[i]) l = std::min(l, m.vertices[v][k]), u = std::max(u, m.vertices[v][k]);
            a[k] = cell(l, k), b[k] = cell(u, k);
        }
        for (int64_t z = a[2]; z <= b[2]; ++z)
            for (int64_t y = a[1]; y <= b[1]; ++y)
                for (int64_t x = a[0]; x <= b[0]; ++x) buckets[key(x, y, z)].push_back(i);
    }
    std::set<std::pair<uint32_t, uint32_t>> found;
    for (const auto& [k, list] : buckets)
        for (std::size_t i = 0; i < list.size(); ++i)
            for (std::size_t j = i + 1; j < list.size(); ++j) {
                const auto &s = m.triangles[list[i]], &t = m.triangles[list[j]];
                int shared = 0, si = -1, ti = -1;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b)
                        if (s[a] == t[b]) ++shared, si = a, ti = b;
                if (shared >= 2) continue;  // neighbours across an edge: orientation covers folds
                bool hit = false;
                auto v = [&](const std::array<uint32_t, 3>& tri, int k) { return m.vertices[tri[k % 3]]; };
                if (shared == 0) {
                    for (int e = 0; e < 3 && !hit; ++e)
                        hit = segment_crosses(v(s, e), v(s, e + 1), v(t, 0), v(t, 1), v(t, 2), h) ||
                              segment_crosses(v(t, e), v(t, e + 1), v(s, 0), v(s, 1), v(s, 2), h);
                } else {  // one shared vertex: the edges opposite it
                    hit = segment_crosses(v(s, si + 1), v(s, si + 2), v(t, 0), v(t, 1), v(t, 2), h) ||
                          segment_crosses(v(t, ti + 1), v(t, ti + 2), v(s, 0), v(s, 1), v(s, 2), h);
                }
                if (hit) found.insert({std::min(list[i], list[j]), std::max(list[i], list[j])});
            }
    r.intersecting_pairs = found.size();
    // Surface to mesh: points of a coarse lattice projected onto the boundary by Newton, and
    // the boundary points between neighbours of that lattice on two sides (by bisection:
    // faces where the field jumps, which no projection reaches).
    auto to_mesh = [&](const P3& p) {
        double best = 1e300;  // triangles in the buckets within a cell (farther ones fail anyway)
        const int64_t c[3] = {cell(p[0], 0), cell(p[1], 1), cell(p[2], 2)};
        for (int64_t z = c[2] - 1; z <= c[2] + 1; ++z)
            for (int64_t y = c[1] - 1; y <= c[1] + 1; ++y)
                for (int64_t x = c[0] - 1; x <= c[0] + 1; ++x) {
                    const auto it = buckets.find(key(x, y, z));
                    if (it == buckets.end()) continue;
                    for (uint32_t t : it->second) {
                        const auto& tri = m.triangles[t];
                        best = std::min(best, distance_to_triangle(p, m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]));
                    }
                }
        if (best > r.surface_to_mesh) r.surface_to_mesh = best, r.worst_surface_point = p;
        if (far && best > 0.5 * h) far->push_back({p, best});
        ++r.samples;
    };
    const int n = samples;
    auto sample = [&](int i, int j, int k) {
        return P3{lo[0] + (hi[0] - lo[0]) * (i + 0.37) / (n + 1), lo[1] + (hi[1] - lo[1]) * (j + 0.53) / (n + 1),
                  lo[2] + (hi[2] - lo[2]) * (k + 0.29) / (n + 1)};
    };
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            for (int k = 0; k <= n; ++k) {
                P3 p = sample(i, j, k);
                if (project(f, p, 1e-12 * h, h) && interior(p) && on_boundary(f, p, h)) to_mesh(p);
                for (int axis = 0; axis < 3; ++axis) {
                    int next[3] = {i, j, k};
                    if (++next[axis] > n) continue;
                    P3 a = sample(i, j, k), b = sample(next[0], next[1], next[2]);
                    const bool in_a = inside(f, a);
                    if (in_a == inside(f, b)) continue;
                    for (int step = 0; step < 80; ++step) {
                        const P3 mid{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
                        (inside(f, mid) == in_a ? a : b) = mid;
                    }
                    if (interior(a)) to_mesh(a);
                }
            }
    return r;
}

}  // namespace fortu::test
