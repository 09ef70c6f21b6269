// runtime/mesh_compare.cpp — mesh topology, Hausdorff distance over a bucket grid, the
// golden comparator.
#include "runtime/mesh_compare.hpp"

#include "runtime/mesh_io.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

namespace fortu {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Triangles of a mesh in cubic buckets, for nearest-triangle queries.
class TriangleBuckets {
public:
    explicit TriangleBuckets(const Mesh& m) : mesh_(m) {
        lo_ = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
               std::numeric_limits<double>::max()};
        Vec hi{-lo_[0], -lo_[1], -lo_[2]};
        for (const Vec& v : m.vertices)
            for (int k = 0; k < 3; ++k) lo_[k] = std::min(lo_[k], v[k]), hi[k] = std::max(hi[k], v[k]);
        const double extent = std::max({hi[0] - lo_[0], hi[1] - lo_[1], hi[2] - lo_[2], 1e-300});
        const double cells = std::clamp(std::cbrt(double(m.triangles.size())), 1.0, 256.0);
        size_ = extent / cells;
        for (int k = 0; k < 3; ++k) n_[k] = std::max(1, int(std::ceil((hi[k] - lo_[k]) / size_)) + 1);
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            int a[3], b[3];
            for (int k = 0; k < 3; ++k) {
                double l = std::numeric_limits<double>::max(), h = -l;
                for (uint32_t v : m.triangles[t]) l = std::min(l, m.vertices[v][k]), h = std::max(h, m.vertices[v][k]);
                a[k] = cell(l, k), b[k] = cell(h, k);
            }
            for (int z = a[2]; z <= b[2]; ++z)
                for (int y = a[1]; y <= b[1]; ++y)
                    for (int x = a[0]; x <= b[0]; ++x) buckets_[key(x, y, z)].push_back(uint32_t(t));
        }
    }

    /// Distance from p to the nearest triangle (infinity for an empty mesh).
    double distance(const Vec& p) const {
        double best = std::numeric_limits<double>::infinity();
        if (mesh_.triangles.empty()) return best;
        const int c[3] = {cell(p[0], 0), cell(p[1], 1), cell(p[2], 2)};
        const int max_ring = std::max({n_[0], n_[1], n_[2]});
        for (int ring = 0; ring <= max_ring; ++ring) {
            if (best < (ring - 1) * size_) break;
            for (int z = c[2] - ring; z <= c[2] + ring; ++z)
                for (int y = c[1] - ring; y <= c[1] + ring; ++y)
                    for (int x = c[0] - ring; x <= c[0] + ring; ++x) {
                        if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != ring) continue;
                        const auto it = buckets_.find(key(x, y, z));
                        if (it == buckets_.end()) continue;
                        for (uint32_t t : it->second) {
                            const auto& tri = mesh_.triangles[t];
                            best = std::min(best, point_triangle_distance(p, mesh_.vertices[tri[0]],
                                                                          mesh_.vertices[tri[1]], mesh_.vertices[tri[2]]));
                        }
                    }
        }
        return best;
    }

private:
    int cell(double x, int k) const { return std::clamp(int((x - lo_[k]) / size_), 0, n_[k] - 1); }
    static int64_t key(int x, int y, int z) { return (int64_t(x) << 42) ^ (int64_t(y) << 21) ^ int64_t(z); }

    const Mesh& mesh_;
    Vec lo_{};
    double size_ = 1;
    int n_[3] = {1, 1, 1};
    std::unordered_map<int64_t, std::vector<uint32_t>> buckets_;
};

double one_sided(const Mesh& from, const TriangleBuckets& to) {
    double worst = 0;
    for (const Vec& v : from.vertices) worst = std::max(worst, to.distance(v));
    for (const auto& t : from.triangles) {
        Vec c{};
        for (uint32_t v : t)
            for (int k = 0; k < 3; ++k) c[k] += from.vertices[v][k] / 3;
        worst = std::max(worst, to.distance(c));
    }
    return worst;
}

}  // namespace

/// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection §5.1.5).
Vec closest_point_on_triangle(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
    const Vec ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    auto at = [&](double v, double w) { return Vec{a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w}; };
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return at(0, 0);
    const Vec bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return at(1, 0);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
    const Vec cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return at(0, 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at(1 - w, w);
    }
    const double denom = 1.0 / (va + vb + vc);
    return at(vb * denom, vc * denom);
}

double point_triangle_distance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
    const Vec d = sub(p, closest_point_on_triangle(p, a, b, c));
    return std::sqrt(dot(d, d));
}

MeshTopology mesh_topology(const Mesh& mesh) {
    MeshTopology t;
    t.vertices = mesh.vertices.size();
    t.triangles = mesh.triangles.size();
    // Directed edge counts per undirected edge.
    std::unordered_map<uint64_t, std::array<int, 2>> edges;
    std::vector<uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const auto& tri : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[k], b = tri[(k + 1) % 3];
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            ++edges[key][a < b ? 0 : 1];
            parent[find(a)] = find(b);
        }
    t.edges = edges.size();
    for (const auto& [key, count] : edges) {
        const int total = count[0] + count[1];
        if (total == 1) ++t.boundary_edges;
        else if (total > 2) ++t.nonmanifold_edges;
        else if (count[0] != 1) ++t.misoriented_edges;
    }
    std::vector<uint8_t> used(mesh.vertices.size(), 0);
    for (const auto& tri : mesh.triangles)
        for (uint32_t v : tri) used[v] = 1;
    std::size_t used_vertices = 0;
    for (uint32_t v = 0; v < used.size(); ++v)
        if (used[v]) {
            ++used_vertices;
            t.components += find(v) == v;
        }
    const long euler = long(used_vertices) - long(t.edges) + long(t.triangles);
    t.genus = (2 * long(t.components) - euler) / 2;
    return t;
}

double hausdorff_distance(const Mesh& a, const Mesh& b) {
    const TriangleBuckets in_a(a), in_b(b);
    return std::max(one_sided(a, in_b), one_sided(b, in_a));
}

OutputComparison compare_mesh_output(const ComparedOutput& compared) {
    OutputComparison result;
    try {
        const Mesh expected = read_mesh(compared.expected_path);
        const Mesh actual = read_mesh(compared.actual_path);
        const MeshTopology e = mesh_topology(expected), a = mesh_topology(actual);
        std::vector<std::string> problems;
        if (!a.closed_manifold())
            problems.push_back(fmt::format("the new mesh is not closed and manifold ({} boundary, {} non-manifold, "
                                           "{} misoriented edges)",
                                           a.boundary_edges, a.nonmanifold_edges, a.misoriented_edges));
        if (a.genus != e.genus || a.components != e.components)
            problems.push_back(fmt::format("{} component(s) of genus {} where {} of genus {} were expected",
                                           a.components, a.genus, e.components, e.genus));
        const double count_tolerance = 0.02 * double(e.triangles);
        if (std::fabs(double(a.triangles) - double(e.triangles)) > count_tolerance)
            problems.push_back(fmt::format("{} triangles where {} were expected (tolerance 2%)", a.triangles, e.triangles));
        const double distance = hausdorff_distance(expected, actual);
        if (!(distance <= compared.tolerance))
            problems.push_back(fmt::format("Hausdorff distance {:.3g} > tolerance {:.3g}", distance, compared.tolerance));
        for (const std::string& p : problems) result.difference += (result.difference.empty() ? "" : "\n") + p;
    } catch (const std::exception& e) {
        result.difference = e.what();
    }
    return result;
}

}  // namespace fortu
