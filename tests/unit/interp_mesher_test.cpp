// tests/unit/interp_mesher_test.cpp — the mesher's own promises, checked on its output in
// memory: vertices on the surface to round-off with the exact normal, pruning to the cells
// near the surface, the same mesh on any number of threads, closing at the domain's border.
// (The end-to-end checks of written files are in cli_mesh_test.cpp, by an independent checker.)
#include "interp_test_support.hpp"

#include "interp/mesher.hpp"
#include "interp/voxel_engine.hpp"
#include "runtime/mesh_compare.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <map>

using namespace fortu;

namespace {

Grid cube(double half, int nodes) {
    Grid g;
    g.dims = 3;
    g.x = g.y = g.z = Axis{-half, half, nodes};
    return g;
}

Model model_of(const std::string& text) {
    auto c = test::compile_text(text);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    return std::move(*c.model);
}

/// Boundary edges (in one triangle), counted over undirected edges.
std::size_t open_edges(const Mesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
    std::size_t open = 0;
    for (const auto& [e, n] : uses) open += n != 2;
    return open;
}

}  // namespace

TEST_CASE("mesh vertices are the field's zeros to round-off, with the exact outward normal") {
    // Radius 0.47: no zero within a thousandth of an edge of a node, where vertices are held
    // back from the node (kEdgeMargin; radius 0.5 passes through nodes).
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN 0.2209 - X*X - Y*Y - Z*Z\n");
    MeshStats stats;
    const Mesh mesh = extract_mesh(m.graph, m.root, cube(1, 33), {}, &stats);
    REQUIRE(mesh.vertices.size() == stats.crossing_edges);
    CHECK(mesh.triangles.size() > 1000);
    CHECK(open_edges(mesh) == 0);
    double worst = 0, worst_normal = 0;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const auto& p = mesh.vertices[v];
        const double r = std::hypot(p[0], p[1], p[2]);
        worst = std::max(worst, std::fabs(r - 0.47));
        for (int k = 0; k < 3; ++k) worst_normal = std::max(worst_normal, std::fabs(mesh.normals[v][k] - p[k] / r));
    }
    CHECK(stats.thin_cells == 0);  // smooth and larger than a cell: every part reached
    CHECK(worst < 1e-14);  // ~20 ulp of the radius
    CHECK(worst_normal < 1e-7);  // the gradient at the last Newton iterate, within 1e-7 of an edge of the vertex
}

TEST_CASE("the octree evaluates only the leaves the surface crosses") {
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN 0.01 - X*X - Y*Y - Z*Z\n");
    MeshStats stats;
    const Grid g = cube(1, 257);
    const Mesh mesh = extract_mesh(m.graph, m.root, g, {}, &stats);
    CHECK(open_edges(mesh) == 0);
    // Interval arithmetic is exact on this function: a leaf (8³ cells) is evaluated iff its
    // closed box reaches both inside and outside the sphere of radius 0.1.
    std::size_t crossed = 0;
    const double h = g.x.step();
    for (int i = 0; i < 32; ++i)
        for (int j = 0; j < 32; ++j)
            for (int k = 0; k < 32; ++k) {
                double near = 0, far = 0;
                for (int c : {i, j, k}) {
                    const double lo = -1 + 8 * c * h, hi = lo + 8 * h;
                    const double n = lo > 0 ? lo : hi < 0 ? -hi : 0, f = std::max(std::fabs(lo), std::fabs(hi));
                    near += n * n;
                    far += f * f;
                }
                crossed += near < 0.01 && far > 0.01;
            }
    CHECK(crossed > 8);
    CHECK(stats.leaves == crossed);
    CHECK(stats.node_evaluations == crossed * 9 * 9 * 9);
    CHECK(stats.node_evaluations * 100 < g.points());
}

TEST_CASE("the mesh is the same on one thread and on several") {
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN (0.6 - X*X - Y*Y) & (0.6 - X*X - Z*Z) & (0.3 + X*Y*Z)\n");
    EvalOptions one, two;
    one.threads = 1;
    two.threads = 3;
    const Mesh a = extract_mesh(m.graph, m.root, cube(1, 41), one);
    const Mesh b = extract_mesh(m.graph, m.root, cube(1, 41), two);
    CHECK(a.vertices == b.vertices);
    CHECK(a.triangles == b.triangles);
    CHECK(a.normals == b.normals);
}

TEST_CASE("a solid the domain cuts is closed on the domain's outer nodes") {
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN 4 - X*X - Y*Y - Z*Z\n");  // radius 2 in [-1, 1]³
    const Mesh mesh = extract_mesh(m.graph, m.root, cube(1, 9));
    CHECK(open_edges(mesh) == 0);
    // The cap sits a thousandth of a cell inside each face.
    for (const auto& p : mesh.vertices) {
        const double outer = std::max({std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
        CHECK(outer == doctest::Approx(0.75 + 0.25 * (1 - 1e-3)).epsilon(1e-12));
    }
}

TEST_CASE("where the field is NaN on a grid plane or line, or zero inside the solid, nodes take it from beside") {
    // X / X is NaN on X = 0, ARCTAN(Y / X) on the Z axis, and the union of the ball's two
    // halves cut at Z = 0 is zero there (B & 0 = 0, 0 | 0 = 0); on 21 nodes over [-1, 1]³
    // those lie on nodes. Counted outside, the nodes split the ball in two (Euler
    // characteristic 4) or bore a tunnel down its axis (0), with caps through its middle.
    for (const char* text : {"ARGUMENT X, Y, Z\nRETURN (0.2209 - X*X - Y*Y - Z*Z) * (X / X)\n",
                             "ARGUMENT X, Y, Z\nRETURN 0.2209 - X*X - Y*Y - Z*Z + 0 * ARCTAN(Y / X)\n",
                             "ARGUMENT X, Y, Z\nVARIABLE B = 0.2209 - X*X - Y*Y - Z*Z\nRETURN (B & Z) | (B & -Z)\n"}) {
        CAPTURE(text);
        const Model m = model_of(text);
        const Mesh mesh = extract_mesh(m.graph, m.root, cube(1, 21));
        CHECK(open_edges(mesh) == 0);
        std::map<std::pair<uint32_t, uint32_t>, int> edges;
        for (const auto& t : mesh.triangles)
            for (int k = 0; k < 3; ++k) ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
        CHECK(long(mesh.vertices.size()) - long(edges.size()) + long(mesh.triangles.size()) == 2);
        double worst = 0;
        for (const auto& p : mesh.vertices) worst = std::max(worst, std::fabs(std::hypot(p[0], p[1], p[2]) - 0.47));
        CHECK(worst < 1e-8);  // a ten-millionth of a cell beside the plane or line: 9.5e-9
    }
}

TEST_CASE("parts thinner than a cell are found by their tetrahedra's edges and meshed on a finer lattice there") {
    // On 21 nodes over [-1, 1]^3 (cells of 0.1) the slab 0.04 < z < 0.06 holds no node but
    // the midpoints of the vertical edges and of the diagonals of the vertical faces and the
    // cells (z = 0.05). Cut by a ball it is a disc that marching tetrahedra on the lattice leave
    // out, and cut from one, a slit they do not open. The expected counts come from the cells
    // themselves, here: each of the seven edges of Kuhn's tetrahedra a cell owns (from its
    // lowest corner to each other corner) against the formula (R0's a & b = a + b - √(a² + b²)):
    // its ends on one side, its midpoint on the other (marching tetrahedra cut an edge where it
    // crosses the surface) and a fiftieth of a cell or more beyond the surface to first order
    // (a twentieth off the main diagonal), |f| / |∇f| (central differences here); the mesher's
    // test of ends near zero leaves none of these out. Refined four times, the slab holds the
    // fine nodes at z = 0.05.
    const Grid grid = cube(1, 21);
    auto at = [](int i) { return -1 + 0.1 * i; };
    auto r0_and = [](double a, double b) { return a + b - std::sqrt(a * a + b * b); };
    auto count_cells = [&](const auto& f, std::array<double, 3>& first) {
        std::size_t n = 0;
        for (int z = 1; z < 19; ++z)  // not the cells on the domain's faces, whose nodes count as outside
            for (int y = 1; y < 19; ++y)
                for (int x = 1; x < 19; ++x) {
                    bool thin = false;
                    for (int dir = 1; dir < 8 && !thin; ++dir) {
                        const int dx = dir & 1, dy = dir >> 1 & 1, dz = dir >> 2;
                        const bool low = f(at(x), at(y), at(z)) > 0, high = f(at(x + dx), at(y + dy), at(z + dz)) > 0;
                        const double cx = at(x) + 0.05 * dx, cy = at(y) + 0.05 * dy, cz = at(z) + 0.05 * dz, d = 1e-6;
                        const double middle = f(cx, cy, cz);
                        const double slope = std::hypot(f(cx + d, cy, cz) - f(cx - d, cy, cz), f(cx, cy + d, cz) - f(cx, cy - d, cz),
                                                        f(cx, cy, cz + d) - f(cx, cy, cz - d)) / (2 * d);
                        thin = low == high && (middle > 0) != low && std::fabs(middle) >= (dir == 7 ? 0.02 : 0.05) * 0.1 * slope;
                    }
                    if (thin && n++ == 0) first = {at(x) + 0.05, at(y) + 0.05, at(z) + 0.05};
                }
        return n;
    };
    // The mesh's pieces (connected by triangles), its Euler characteristic and its volume.
    auto pieces = [](const Mesh& mesh) {
        std::vector<uint32_t> parent(mesh.vertices.size());
        for (uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
        auto root = [&](uint32_t v) {
            while (parent[v] != v) v = parent[v] = parent[parent[v]];
            return v;
        };
        for (const auto& t : mesh.triangles) parent[root(t[1])] = root(t[0]), parent[root(t[2])] = root(t[0]);
        std::size_t n = 0;
        for (uint32_t v = 0; v < parent.size(); ++v) n += root(v) == v;
        return n;
    };
    auto euler = [](const Mesh& mesh) {
        std::map<std::pair<uint32_t, uint32_t>, int> edges;
        for (const auto& t : mesh.triangles)
            for (int k = 0; k < 3; ++k) ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
        return long(mesh.vertices.size()) - long(edges.size()) + long(mesh.triangles.size());
    };
    auto volume = [](const Mesh& mesh) {
        double v = 0;
        for (const auto& t : mesh.triangles) {
            const auto &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
            v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
        }
        return v;
    };
    const double pi = std::acos(-1.0);
    // The model meshed with stats, its thin cells and the first one's centre checked against
    // the formula's count, which is returned.
    auto mesh_counted = [&](const Model& m, const auto& f, MeshStats& stats, Mesh& mesh) {
        mesh = extract_mesh(m.graph, m.root, grid, {}, &stats);
        std::array<double, 3> first{};
        const std::size_t expected = count_cells(f, first);
        CHECK(stats.thin_cells == expected);
        for (int a = 0; a < 3; ++a) CHECK(stats.first_thin[std::size_t(a)] == doctest::Approx(first[std::size_t(a)]).epsilon(1e-12));
        return expected;
    };
    SUBCASE("a disc") {
        const Model m = model_of("ARGUMENT X, Y, Z\nRETURN (0.0001 - (Z - 0.05)^2) & (0.25 - X*X - Y*Y - Z*Z)\n");
        MeshStats stats;
        Mesh mesh;
        const std::size_t expected = mesh_counted(m, [&](double x, double y, double z) {
            return r0_and(0.0001 - (z - 0.05) * (z - 0.05), 0.25 - x * x - y * y - z * z);
        }, stats, mesh);
        // The 80 centres (x, y, 0.05) with x² + y² < 0.2475, and 6 cells beyond them on the rim
        // with the midpoint of a vertical edge or face diagonal inside.
        CHECK(expected == 86);
        // The rim's other cells have no midpoint inside: they are reached across the refined cells' faces.
        CHECK(stats.refined_cells > expected);
        CHECK(stats.refinement_left == 0);
        // One closed piece, a sphere's topology, of the disc's volume: π (0.25 - 0.05²) 0.02 to
        // within 3% (marching tetrahedra cut the rim's corners).
        CHECK(open_edges(mesh) == 0);
        CHECK(pieces(mesh) == 1);
        CHECK(euler(mesh) == 2);
        CHECK(volume(mesh) == doctest::Approx(pi * (0.25 - 0.0025) * 0.02).epsilon(0.03));
        // Every vertex on the surface: a face of the slab or the ball.
        for (const auto& p : mesh.vertices) {
            const double slab = std::fabs(std::fabs(p[2] - 0.05) - 0.01), ball = std::fabs(std::hypot(p[0], p[1], p[2]) - 0.5);
            REQUIRE(std::min(slab, ball) < 1e-12);
        }
    }
    SUBCASE("a slit") {
        const Model m = model_of("ARGUMENT X, Y, Z\nRETURN (0.49 - X*X - Y*Y - Z*Z) & ((Z - 0.05)^2 - 0.0001)\n");
        MeshStats stats;
        Mesh mesh;
        const std::size_t expected = mesh_counted(m, [&](double x, double y, double z) {
            return r0_and(0.49 - x * x - y * y - z * z, (z - 0.05) * (z - 0.05) - 0.0001);
        }, stats, mesh);
        // By the centres alone 128 (140 on the other side, 12 of them within a fiftieth of a cell
        // of the surface); with the vertical edges' and face diagonals' midpoints 147.
        CHECK(expected == 147);
        CHECK(stats.refinement_left == 0);
        // The ball cut in two: two closed pieces, each a sphere's topology, and the slit's
        // volume gone (without it the volume would be 1.43).
        CHECK(open_edges(mesh) == 0);
        CHECK(pieces(mesh) == 2);
        CHECK(euler(mesh) == 4);
        const double cap = pi * 0.02 * (0.49 - 0.0025 - 0.0001 / 3);  // the slab's part of the ball, near enough
        CHECK(volume(mesh) == doctest::Approx(4 * pi * 0.343 / 3 - cap).epsilon(0.01));
        // Without stats asked for, the mesh is the same.
        CHECK(extract_mesh(m.graph, m.root, grid).triangles == mesh.triangles);
    }
}

TEST_CASE("a slab whose faces only graze its cells' corners is refined, not joined across by marching tetrahedra") {
    // The slab 0.003 < X + Y + Z < 0.297 on 21 nodes over [-1, 1]^3 (cells of 0.1): 1.7 cells
    // thick across, its faces a thirtieth of a cell off the lattice's diagonal planes through
    // nodes X + Y + Z = 0 and 0.3. A cell whose lowest corner is on the first has both ends of
    // its main diagonal outside and the rest inside, and marching tetrahedra join the two
    // outsides along that diagonal: a tube through the slab, 0.85 cells from its faces at the
    // cell's centre and 0.018 cells from it. That near, a thin cell's centre counted as on the
    // mesh, and was not refined (Chainik at 64 nodes kept such a tube, 0.54 cells off, its
    // centre 0.05 cells from it); and here the tube's six faces are as near it as each other,
    // their normals summing to nothing, so only the normals at one nearest point tell its side.
    const Model m = model_of("ARGUMENT X, Y, Z\nRETURN (X + Y + Z - 0.003) & (0.297 - X - Y - Z)\n");
    const Grid grid = cube(1, 21);
    const double h = 0.1;
    MeshStats stats;
    const Mesh mesh = extract_mesh(m.graph, m.root, grid, {}, &stats);
    CHECK(open_edges(mesh) == 0);
    // The thin cells: those whose lowest corner (i, j, k) has i + j + k = 30, none on the
    // domain's faces (1 ≤ i, j, k ≤ 18); each refined.
    std::size_t grazing = 0;
    for (int i = 1; i <= 18; ++i)
        for (int j = 1; j <= 18; ++j) grazing += 30 - i - j >= 1 && 30 - i - j <= 18;
    CHECK(grazing == 241);
    CHECK(stats.thin_cells == grazing);
    CHECK(stats.refined_cells >= grazing);
    CHECK(stats.refinement_left == 0);
    // The mesh's points away from the domain's faces (where the caps close the slab) on the
    // slab's faces: its vertices and the triangles' centroids and edges' midpoints. Every
    // vertex is on one of the two planes, so a triangle off them is one joining both.
    double farthest = 0;
    std::array<double, 3> where{};
    for (const auto& t : mesh.triangles)
        for (const auto& w : {std::array<double, 3>{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5},
                              {1.0 / 3, 1.0 / 3, 1.0 / 3}}) {
            std::array<double, 3> p{};
            for (int a = 0; a < 3; ++a) p[a] = w[0] * mesh.vertices[t[0]][a] + w[1] * mesh.vertices[t[1]][a] + w[2] * mesh.vertices[t[2]][a];
            if (std::max({std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])}) > 1 - 0.6 * h) continue;
            const double sum = p[0] + p[1] + p[2];
            const double d = std::min(std::fabs(sum - 0.003), std::fabs(0.297 - sum)) / std::sqrt(3.0);
            if (d > farthest) farthest = d, where = p;
        }
    INFO("farthest ", farthest / h, " cells at ", where[0], " ", where[1], " ", where[2]);
    CHECK(farthest < 1e-9 * h);
}

TEST_CASE("a spike's tip that marching tetrahedra cut off is put back by a vertex on the surface") {
    // A cone of half-angle 8.5° with its apex at (0.013, 0.021, 0.37), off the lattice of 25
    // nodes (cells of 1/12): its last 3.4 cells of height are thinner than a cell, and the
    // mesh without this pass stops 1.96 cells from the apex (measured with the pass turned
    // off). The probes round the cap's bent triangles find the surface there more than 0.4
    // cells from the mesh and put it in.
    const Model m = model_of("ARGUMENT X, Y, Z\nVARIABLE R = SQRT((X - 0.013) * (X - 0.013) + (Y - 0.021) * (Y - 0.021))\n"
                             "RETURN ((0.37 - Z) * 0.15 - R) & (Z + 0.5)\n");
    const Grid grid = cube(1, 25);
    const double h = 2.0 / 24;
    for (int threads : {1, 2}) {
        CAPTURE(threads);
        EvalOptions options;
        options.threads = threads;
        MeshStats stats;
        const Mesh mesh = extract_mesh(m.graph, m.root, grid, options, &stats);
        CHECK(open_edges(mesh) == 0);
        CHECK(stats.cover.far >= 1);
        CHECK(stats.cover.inserted >= 1);
        CHECK(stats.cover.refused == 0);
        double apex = INFINITY;
        for (const auto& t : mesh.triangles)
            apex = std::min(apex, point_triangle_distance({0.013, 0.021, 0.37}, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
        CHECK(apex < 0.5 * h);
        // The new vertices (the last ones) are on the surface to round-off, with the field's
        // outward normal.
        const PointEvaluator field(m.graph, m.root);
        for (std::size_t v = mesh.vertices.size() - stats.cover.inserted; v < mesh.vertices.size(); ++v) {
            const PointValue at = field(mesh.vertices[v]);
            CHECK(std::fabs(at.value) < 1e-12);
            const double g = std::hypot(at.gradient[0], at.gradient[1], at.gradient[2]);
            for (int k = 0; k < 3; ++k) CHECK(mesh.normals[v][std::size_t(k)] == doctest::Approx(-at.gradient[std::size_t(k)] / g).epsilon(1e-9));
        }
    }
}

TEST_CASE("a twisted blade's edge that marching tetrahedra cut across is put back by vertices on it") {
    // A blade 11° thin (its sides the crease of ABS, which the feature pass does not trace)
    // whose edge U = 0.37, V = 0.021 turns a radian every quarter unit of Z, on 25 nodes
    // (cells of 1/12). Newton from beside the edge steps from one side to the other: alone it
    // zigzagged without landing, and the edge stayed 0.60 cells from the mesh (with points put
    // in from 0.3 cells off, 0.46 without probes stepping onto both sides' tangent planes at
    // once and 0.31 with them; 0.24 from 0.25 cells off).
    const Model m = model_of("ARGUMENT X, Y, Z\nVARIABLE C = COS(4*Z)\nVARIABLE S = SIN(4*Z)\n"
                             "VARIABLE U = X*C + Y*S\nVARIABLE V = Y*C - X*S\n"
                             "RETURN ((0.37 - U) * 0.1 - ABS(V - 0.021)) & (X*X + Y*Y - 0.0025) & (0.5 - Z) & (Z + 0.5)\n");
    const Grid grid = cube(1, 25);
    const double h = 2.0 / 24;
    MeshStats stats;
    const Mesh mesh = extract_mesh(m.graph, m.root, grid, {}, &stats);
    CHECK(open_edges(mesh) == 0);
    CHECK(stats.cover.inserted >= 1);
    double farthest = 0;
    for (int i = 0; i <= 180; ++i) {
        const double z = -0.45 + 0.9 * i / 180, c = std::cos(4 * z), s = std::sin(4 * z);
        const std::array<double, 3> edge{0.37 * c - 0.021 * s, 0.37 * s + 0.021 * c, z};
        double nearest = INFINITY;
        for (const auto& t : mesh.triangles)
            nearest = std::min(nearest, point_triangle_distance(edge, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
        farthest = std::max(farthest, nearest);
    }
    INFO("edge farthest ", farthest / h, " cells");
    CHECK(farthest < 0.4 * h);
    // The new vertices are on the surface: within the billionth of a cell Newton stops at, to
    // first order (beside a crease the value left there is larger than the cone's 1e-12), or
    // exactly (the blade's corners at Z = ±0.5, where its gradient is NaN).
    const PointEvaluator field(m.graph, m.root);
    for (std::size_t v = mesh.vertices.size() - stats.cover.inserted; v < mesh.vertices.size(); ++v) {
        const PointValue at = field(mesh.vertices[v]);
        CHECK((at.value == 0 || std::fabs(at.value) < 1e-9 * h * std::hypot(at.gradient[0], at.gradient[1], at.gradient[2])));
    }
}

TEST_CASE("meshing refuses a 2D grid") {
    const Model m = model_of("ARGUMENT X, Y\nRETURN 0.25 - X*X - Y*Y\n");
    Grid g;
    g.dims = 2;
    g.x = g.y = Axis{-1, 1, 9};
    CHECK_THROWS_WITH_AS(extract_mesh(m.graph, m.root, g), "a mesh needs a 3D model (X, Y, Z)", std::invalid_argument);
}
