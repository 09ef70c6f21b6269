// tests/unit/interp_mesh_features_test.cpp — sharp features on the mesh (mesh_features.hpp):
// a box's corners are vertices and its edges are mesh edges to round-off, so its mesh is the
// box exactly (its volume to round-off); the Steinmetz solid's edge vertices lie on the two
// cylinders' intersection and are joined along it; the mesh stays closed, oriented and free
// of degenerate triangles. (cli_mesh_test.cpp checks written files with the independent checker.)
#include "interp_test_support.hpp"

#include "interp/lower.hpp"
#include "interp/mesher.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <set>

using namespace fortu;

namespace {

using Vec = std::array<double, 3>;

Grid cube(double half, int nodes) {
    Grid g;
    g.dims = 3;
    g.x = g.y = g.z = Axis{-half, half, nodes};
    return g;
}

Model model_of(const std::string& text, const std::string& rsystem = "") {
    CompileOptions options;
    if (!rsystem.empty()) options.rsystem = parse_rsystem(rsystem);
    auto c = test::compile_text(text, options);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    return std::move(*c.model);
}

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double segment_distance(const Vec& p, const Vec& a, const Vec& b) {
    const Vec d = sub(b, a);
    const double t = std::clamp(dot(sub(p, a), d) / dot(d, d), 0.0, 1.0);
    const Vec x = sub(p, {a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]});
    return std::sqrt(dot(x, x));
}

/// Closed, manifold and oriented (each directed edge once, its reverse once), no triangle
/// below 1e-10 cell² (the independent checker's bound), and V − E + F. Returns the edges.
std::set<std::pair<uint32_t, uint32_t>> check_topology(const Mesh& m, double h, int euler) {
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    std::size_t degenerate = 0;
    for (const auto& t : m.triangles) {
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
        const Vec n = cross(sub(m.vertices[t[1]], m.vertices[t[0]]), sub(m.vertices[t[2]], m.vertices[t[0]]));
        degenerate += !(std::sqrt(dot(n, n)) / 2 > 1e-10 * h * h);
    }
    std::size_t bad = 0;
    std::set<std::pair<uint32_t, uint32_t>> edges;
    for (const auto& [e, n] : directed) {
        const auto back = directed.find({e.second, e.first});
        bad += n != 1 || back == directed.end() || back->second != 1;
        edges.insert({std::min(e.first, e.second), std::max(e.first, e.second)});
    }
    std::vector<char> used(m.vertices.size(), 0);
    for (const auto& t : m.triangles)
        for (uint32_t v : t) used[v] = 1;
    CHECK(bad == 0);
    CHECK(degenerate == 0);
    CHECK(std::count(used.begin(), used.end(), 0) == 0);
    CHECK(long(m.vertices.size()) - long(edges.size()) + long(m.triangles.size()) == euler);
    return edges;
}

double signed_volume(const Mesh& m) {
    double v = 0;
    for (const auto& t : m.triangles) v += dot(m.vertices[t[0]], cross(m.vertices[t[1]], m.vertices[t[2]])) / 6;
    return v;
}

}  // namespace

TEST_CASE("a box's corners are mesh vertices and its edges mesh edges, to round-off") {
    // Half sides 0.8, 0.6, 0.45 on 24 nodes over [-1, 1]: no face on a grid plane.
    const Vec half{0.8, 0.6, 0.45};
    const struct {
        const char* name;
        std::string text, rsystem;
    } cases[] = {{"R0", "ARGUMENT X, Y, Z\nRETURN (0.64 - X*X) & (0.36 - Y*Y) & (0.2025 - Z*Z)\n", "r0"},
                 {"alpha=0.5", "ARGUMENT X, Y, Z\nRETURN (0.64 - X*X) & (0.36 - Y*Y) & (0.2025 - Z*Z)\n", "alpha=0.5"},
                 {"MIN", "ARGUMENT X, Y, Z\nRETURN MIN(MIN(0.64 - X*X, 0.36 - Y*Y), 0.2025 - Z*Z)\n", ""},
                 // R0 spelt out, as RANOK scripts often write it.
                 {"R0 written out",
                  "ARGUMENT X, Y, Z\nVARIABLE A = 0.64 - X*X;\nVARIABLE B = 0.36 - Y*Y;\nVARIABLE C = 0.2025 - Z*Z;\n"
                  "VARIABLE W = A + B - SQRT(A*A + B*B);\nRETURN W + C - SQRT(W*W + C*C);\n",
                  ""}};
    for (const auto& c : cases) {
        CAPTURE(c.name);
        const Model m = model_of(c.text, c.rsystem);
        const Grid g = cube(1, 24);
        const double h = g.x.step();
        MeshStats stats;
        const Mesh mesh = extract_mesh(m.graph, m.root, g, {}, &stats);
        const auto edges = check_topology(mesh, h, 2);
        CHECK(stats.features.corner_vertices == 8);
        // Every corner is a vertex.
        double worst_corner = 0;
        for (int k = 0; k < 8; ++k) {
            const Vec corner{(k & 1 ? 1 : -1) * half[0], (k & 2 ? 1 : -1) * half[1], (k & 4 ? 1 : -1) * half[2]};
            double best = 1e300;
            for (const Vec& v : mesh.vertices) best = std::min(best, std::sqrt(dot(sub(v, corner), sub(v, corner))));
            worst_corner = std::max(worst_corner, best);
        }
        CHECK(worst_corner <= 1e-9);
        // Every point of every box edge is on a mesh edge.
        double worst_edge = 0;
        for (int axis = 0; axis < 3; ++axis)
            for (int k = 0; k < 4; ++k)
                for (int s = 0; s <= 40; ++s) {
                    Vec p;
                    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
                    p[axis] = half[axis] * (2.0 * s / 40 - 1);
                    p[u] = (k & 1 ? 1 : -1) * half[u];
                    p[w] = (k & 2 ? 1 : -1) * half[w];
                    double best = 1e300;
                    for (const auto& [a, b] : edges)
                        best = std::min(best, segment_distance(p, mesh.vertices[a], mesh.vertices[b]));
                    worst_edge = std::max(worst_edge, best);
                }
        CHECK(worst_edge <= 1e-9);
        // Faces planar with exact vertices, edges and corners: the mesh is the box.
        CHECK(signed_volume(mesh) == doctest::Approx(8 * half[0] * half[1] * half[2]).epsilon(1e-12));
    }
}

TEST_CASE("the Steinmetz solid's edge vertices are on both cylinders and joined along the edge") {
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN (1 - X*X - Y*Y) & (1 - X*X - Z*Z)\n");
    // Y and Z nodes offset from each other: on a symmetric grid the Kuhn split's (0, 1, 1)
    // diagonals lie in the plane y = z and their marching-tetrahedra vertices on the curve.
    Grid g = cube(1.3, 33);
    g.y = Axis{-1.27, 1.33, 33};
    g.z = Axis{-1.31, 1.29, 33};
    const double h = g.x.step();
    MeshStats stats;
    const Mesh mesh = extract_mesh(m.graph, m.root, g, {}, &stats);
    const auto edges = check_topology(mesh, h, 2);
    // The distance to each cylinder, to first order (exact enough at 1e-9).
    auto off_curve = [](const Vec& p) {
        const double r1 = std::hypot(p[0], p[1]), r2 = std::hypot(p[0], p[2]);
        return std::max(std::fabs(r1 - 1), std::fabs(r2 - 1));
    };
    std::vector<char> on(mesh.vertices.size(), 0);
    std::size_t on_curve = 0, near_curve = 0;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        on[v] = off_curve(mesh.vertices[v]) <= 1e-9;
        on_curve += on[v];
        near_curve += off_curve(mesh.vertices[v]) <= 0.5 * h;
    }
    // Every feature vertex the pass placed is on the curve (and no other vertex is).
    CHECK(on_curve == stats.features.edge_vertices + stats.features.corner_vertices);
    // The two ellipses (y = ±z) are 15.3 long: at least one vertex per 1.5 cells of it.
    CHECK(on_curve * 1.5 * h >= 15.3);
    std::size_t joined = 0;
    for (const auto& [a, b] : edges) joined += on[a] && on[b];
    INFO(on_curve, " on the curve, ", near_curve, " within half a cell, ", joined, " edges along it");
    // Chains: the four arcs between the points (±1, 0, 0), where the cylinders touch and the
    // curve cannot be traced, each with one edge fewer than vertices.
    CHECK(joined + 4 >= on_curve);
    // Points of the curve to the mesh, and to its edges along the curve.
    double to_mesh = 0, to_chain_median = 0;
    std::vector<double> chain;
    for (int s = 0; s < 200; ++s) {
        const double t = 2 * M_PI * (s + 0.5) / 200;
        for (double sign : {1.0, -1.0}) {
            const Vec p{std::cos(t), std::sin(t), sign * std::sin(t)};
            double best = 1e300, best_chain = 1e300;
            for (const auto& tri : mesh.triangles)
                for (int k = 0; k < 3; ++k) {
                    const uint32_t a = tri[k], b = tri[(k + 1) % 3];
                    const double d = segment_distance(p, mesh.vertices[a], mesh.vertices[b]);
                    best = std::min(best, d);
                    if (on[a] && on[b]) best_chain = std::min(best_chain, d);
                }
            to_mesh = std::max(to_mesh, best);
            chain.push_back(best_chain);
        }
    }
    std::sort(chain.begin(), chain.end());
    to_chain_median = chain[chain.size() / 2];
    INFO("curve to the mesh's edges: ", to_mesh / h, " cells at most; to the edges along it: median ", to_chain_median / h,
         " cells");
    CHECK(to_chain_median <= 0.05 * h);  // a chord's sagitta, L² κ / 8: at most 0.043 h for L = √3 h, κ ≤ √2
    CHECK(to_mesh <= 0.2 * h);  // near (±1, 0, 0), where the curve is not traced, marching tetrahedra's cut
}

TEST_CASE("a corner where an operand's slope is infinite (a power below 1 at its root) is a mesh vertex") {
    // RANOK's economf1_3: X^0.2 and Y^0.2 are NaN below their roots and their slopes infinite
    // there, so the first-order estimate never reaches the root (it says 5X) and Newton's step
    // from X overshoots to -4X. The corner is found by the cell's corners and by bisection to
    // where the operand ends; it was fanned from a point of the edge 0.75 cells off before.
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN (0.2*X^0.2) & (4*Y) & (2*Z+1) & (0.25*Y^0.2)\n");
    const Grid g = cube(1, 65);
    const double h = g.x.step();
    const Mesh mesh = extract_mesh(m.graph, m.root, g, {});
    check_topology(mesh, h, 2);
    const Vec corner{0, 0, -0.5};
    double best = 1e300;
    for (const Vec& v : mesh.vertices) best = std::min(best, std::sqrt(dot(sub(v, corner), sub(v, corner))));
    CHECK(best <= 1e-9);
}
