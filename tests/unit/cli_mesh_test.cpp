// tests/unit/cli_mesh_test.cpp — `fortu run -o model.stl|.obj|.ply` end to end, each mesh read
// back and checked by the independent checker (mesh_checker.hpp): closed, manifold, oriented
// outward, no degenerate triangles, no self-intersections, within half a cell of the true
// surface both ways. Models: an R0 box, a Steinmetz solid, a pentagon prism, a slab around the
// LRFM FLOZ3 triangle (in R0, Rα = 0.5 and MINMAX), RANOK scripts on their header domains and
// the 3D examples.
#include "cli_support.hpp"
#include "mesh_checker.hpp"
#include "test_support.hpp"

#include "grammar/diagnostic.hpp"
#include "interp/lower.hpp"

#include <doctest/doctest.h>

#include <fmt/format.h>

#include <filesystem>

using namespace fortu;
using fortu::test::quote;
using fortu::test::run_fortu;
using fortu::test::P3;

namespace {

struct Case {
    std::string name;
    std::string path;        ///< the script
    P3 lo, hi;               ///< its domain
    int size;                ///< nodes per axis
    std::string rsystem;     ///< "" or r0 / alpha=0.5 / minmax
};

Model load(const std::string& path, const std::string& rsystem) {
    std::string error;
    auto source = SourceFile::load(path, error);
    REQUIRE_MESSAGE(source, error);
    CompileOptions options;
    if (!rsystem.empty()) options.rsystem = parse_rsystem(rsystem);
    options.include_dirs = {std::string(FORTU_SOURCE_DIR) + "/stdlib"};
    DiagnosticSink sink;
    std::optional<Model> model = compile(source, options, sink);
    REQUIRE_MESSAGE(model, sink.render_all());
    return std::move(*model);
}

/// Meshes the case to PLY and checks it. `distance_cells`: the bound on both one-sided
/// distances, in cells: half a cell on smooth surfaces; where the solid has sharp edges and
/// corners, marching tetrahedra cut them off by up to a cell's half diagonal (√3/2 ≈ 0.87),
/// since its vertices lie on grid edges; the feature pass puts most of them back, but keeps
/// the cut where its tests fail (README "Meshes").
test::MeshCheck mesh_and_check(const Case& c, const test::ScratchDir& dir, double distance_cells = 0.5) {
    const std::string out = dir / (c.name + ".ply");
    const std::string domain = fmt::format("{}:{},{}:{},{}:{}", c.lo[0], c.hi[0], c.lo[1], c.hi[1], c.lo[2], c.hi[2]);
    const auto run = run_fortu(fmt::format("run {} --size {} --domain {} -o {}{}", quote(c.path), c.size, domain,
                                           quote(out), c.rsystem.empty() ? "" : " --rsystem " + c.rsystem));
    REQUIRE_MESSAGE(run.status == 0, run.out);
    const Model model = load(c.path, c.rsystem);
    const PointEvaluator field(model.graph, model.root);
    double h = 0;
    for (int k = 0; k < 3; ++k) h = std::max(h, (c.hi[k] - c.lo[k]) / (c.size - 1));
    const test::CheckedMesh mesh = test::read_binary_ply(out);
    const test::MeshCheck r = test::check_mesh(mesh, field, c.lo, c.hi, h);
    INFO(c.name, " ", c.rsystem, ": ", r.triangles, " triangles, volume ", r.signed_volume, ", mesh->surface ",
         r.mesh_to_surface / h, " cells, surface->mesh ", r.surface_to_mesh / h, " cells (", r.samples,
         " samples), normals wrong ", r.normals_wrong, "/", r.normals_checked);
    CHECK(r.triangles > 100);
    CHECK(r.open_edges == 0);
    CHECK(r.overused_edges == 0);
    CHECK(r.same_direction_edges == 0);
    CHECK(r.degenerate == 0);
    CHECK(r.intersecting_pairs == 0);
    CHECK(r.signed_volume > 0);
    CHECK(r.normals_wrong * 100 <= r.normals_checked);  // ±h/8 may reach past a thin part or a sharp edge
    if (distance_cells > 0) {
        CHECK(r.mesh_to_surface <= distance_cells * h);
        CHECK(r.surface_to_mesh <= distance_cells * h);
        CHECK(r.samples > 20);
    }
    return r;
}

/// The distance bound on solids with sharp edges and corners, in cells (see mesh_and_check).
constexpr double kSharp = 0.87;

const char* kBox = "ARGUMENT X, Y, Z;\nRETURN (1 - X^2) & (0.75^2 - Y^2) & (0.5^2 - Z^2);\n";
const char* kSteinmetz = "ARGUMENT X, Y, Z;\nRETURN (1 - X^2 - Y^2) & (1 - X^2 - Z^2);\n";
const char* kPentagonPrism =
    "ARGUMENT X, Y, Z;\nRETURN (4 - Y) & (Y + 3) & (7 - X) & (X + 4 - Y) & (Y + X + 3) & (4 - Z^2);\n";

std::string shared_script(const std::string& name) {
    return std::string(FORTU_SHARED_DIR) + "/data/ranok-scripts/" + name;
}

}  // namespace

TEST_CASE("meshes of sharp R-function solids are closed, oriented, intersection-free and on the surface") {
    test::ScratchDir dir;
    const std::string box = dir.write("box.fortu", kBox);
    const std::string steinmetz = dir.write("steinmetz.fortu", kSteinmetz);
    const std::string prism = dir.write("prism.fortu", kPentagonPrism);
    const std::string triangle = dir.write(
        "triangle.fortu", test::read_file(std::string(FORTU_SOURCE_DIR) + "/examples/lrfm_triangle_floz.fortu") +
                              "");
    // The FLOZ3 is zero on the triangle and positive elsewhere: the solid is the slab SS < 0.1.
    const std::string slab = dir.write("slab.fortu", [&] {
        std::string text = test::read_file(triangle);
        text.replace(text.rfind("RETURN SS;"), 10, "RETURN 0.1 - SS;");
        return text;
    }());
    for (const std::string rsystem : {"r0", "alpha=0.5", "minmax"}) {
        SUBCASE(rsystem.c_str()) {
            mesh_and_check({"box", box, {-1.3, -1.3, -1.3}, {1.3, 1.3, 1.3}, 27, rsystem}, dir, kSharp);
            // Sharp features: the box's corners (on grid planes here: x = ±1, z = ±0.5) are vertices.
            const test::CheckedMesh written = test::read_binary_ply(dir / "box.ply");
            double worst = 0;
            for (int k = 0; k < 8; ++k) {
                const P3 corner{k & 1 ? 1.0 : -1.0, k & 2 ? 0.75 : -0.75, k & 4 ? 0.5 : -0.5};
                double best = 1e300;
                for (const P3& v : written.vertices)
                    best = std::min(best, std::sqrt(test::dot3(test::minus(v, corner), test::minus(v, corner))));
                worst = std::max(worst, best);
            }
            CHECK(worst <= 1e-9);
            mesh_and_check({"steinmetz", steinmetz, {-1.3, -1.3, -1.3}, {1.3, 1.3, 1.3}, 33, rsystem}, dir, kSharp);
            mesh_and_check({"prism", prism, {-5, -4, -3}, {8, 5, 3}, 33, rsystem}, dir, kSharp);
        }
    }
    mesh_and_check({"floz3_slab", slab, {-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}, 33, ""}, dir);
}

TEST_CASE("meshes of RANOK scripts on their header domains and of the 3D examples") {
    test::ScratchDir dir;
    // Half-extents from each script's first comment line (//x : 6.5 ; y : 6.5 ; z : 6.5).
    // Chainik's flutes use ARCTAN(Y/X), which jumps at X = 0: the sign changes there without a
    // zero, so the mesh has faces on the jump that no Newton projection reaches; its distances
    // are not checked (-1), its topology is. The pawn's pieces meet in sharp rims (0.58 of a
    // cell with --size 41 along its long axis, square cells).
    const struct {
        const char* script;
        P3 half;
        double distance_cells;
    } scripts[] = {{"Tor.fortu", {6.5, 6.5, 6.5}, 0.5},   {"Pawn.fortu", {4, 9, 4}, kSharp},
                   {"Cub.fortu", {3.5, 3.5, 3.5}, kSharp}, {"TeaCup.fortu", {6, 5, 4.5}, 0.5},
                   {"Chainik.fortu", {8, 5, 8}, -1}};
    for (const auto& s : scripts) {
        const std::string path = shared_script(s.script);
        if (!std::filesystem::exists(path)) continue;
        mesh_and_check({s.script, path, {-s.half[0], -s.half[1], -s.half[2]}, {s.half[0], s.half[1], s.half[2]}, 41, ""},
                       dir, s.distance_cells);
    }
    const std::string examples = std::string(FORTU_SOURCE_DIR) + "/examples/";
    mesh_and_check({"pawn", examples + "pawn.fortu", {-4, -1, -4}, {4, 8, 4}, 41, ""}, dir);
    mesh_and_check({"singular_box", examples + "singular_box.fortu", {-1.25, -1.25, -1.25}, {1.25, 1.25, 1.25}, 26, ""},
                   dir, kSharp);
    mesh_and_check({"floz3_sphere80", examples + "floz3_sphere80.fortu", {-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 25, ""},
                   dir);
}

TEST_CASE("STL (binary, ASCII) and OBJ hold the same mesh as PLY") {
    test::ScratchDir dir;
    const std::string model = dir.write("steinmetz.fortu", kSteinmetz);
    const std::string args = " --size 17 --domain -1.2:1.2,-1.2:1.2,-1.2:1.2 -o ";
    REQUIRE(run_fortu("run " + quote(model) + args + quote(dir / "m.ply")).status == 0);
    REQUIRE(run_fortu("run " + quote(model) + args + quote(dir / "m.stl")).status == 0);
    REQUIRE(run_fortu("run " + quote(model) + args + quote(dir / "a.stl") + " --ascii").status == 0);
    REQUIRE(run_fortu("run " + quote(model) + args + quote(dir / "m.obj")).status == 0);
    const test::CheckedMesh ply = test::read_binary_ply(dir / "m.ply");
    const test::CheckedMesh stl = test::read_binary_stl(dir / "m.stl");
    CHECK(stl.triangles.size() == ply.triangles.size());
    CHECK(stl.vertices.size() == ply.vertices.size());   // float32 does not merge vertices
    const std::string ascii = dir.read("a.stl");
    CHECK(ascii.rfind("solid fortu\nfacet normal ", 0) == 0);
    std::size_t facets = 0;
    for (std::size_t at = ascii.find("endfacet"); at != std::string::npos; at = ascii.find("endfacet", at + 1)) ++facets;
    CHECK(facets == ply.triangles.size());
    const std::string obj = dir.read("m.obj");
    std::size_t v = 0, vn = 0, f = 0;
    std::istringstream lines(obj);
    for (std::string line; std::getline(lines, line);) {
        v += line.rfind("v ", 0) == 0;
        vn += line.rfind("vn ", 0) == 0;
        f += line.rfind("f ", 0) == 0;
    }
    CHECK(v == ply.vertices.size());
    CHECK(vn == ply.vertices.size());
    CHECK(f == ply.triangles.size());
    // Normals are the exact outward unit normals: on the cylinder x² + y² = 1, (x, y, 0).
    std::istringstream again(obj);
    std::vector<P3> vertices, normals;
    for (std::string line; std::getline(again, line);) {
        std::istringstream w(line);
        std::string kind;
        P3 p;
        w >> kind >> p[0] >> p[1] >> p[2];
        if (kind == "v") vertices.push_back(p);
        if (kind == "vn") normals.push_back(p);
    }
    std::size_t on_cylinder = 0;
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const P3& p = vertices[i];
        if (std::fabs(p[0] * p[0] + p[1] * p[1] - 1) > 1e-9 || std::fabs(p[0] * p[0] + p[2] * p[2] - 1) < 0.05) continue;
        ++on_cylinder;
        // the gradient at the last Newton iterate, within 1e-7 of an edge of the vertex
        CHECK(std::fabs(normals[i][0] - p[0]) < 1e-6);
        CHECK(std::fabs(normals[i][1] - p[1]) < 1e-6);
        CHECK(std::fabs(normals[i][2]) < 1e-6);
    }
    CHECK(on_cylinder > 50);
}

TEST_CASE("mesh usage errors") {
    test::ScratchDir dir;
    const std::string disc = quote(dir.write("disc.fortu", "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n"));
    const std::string ball = quote(dir.write("ball.fortu", "ARGUMENT X, Y, Z;\nRETURN 0.25 - X*X - Y*Y - Z*Z;\n"));
    auto r = run_fortu("run " + disc + " -o " + quote(dir / "d.stl"));
    CHECK(r.status == 2);
    CHECK(r.out == fmt::format("fortu: error: -o {}: a mesh needs a 3D model (X, Y, Z); this one has 2 argument(s)\n",
                               dir / "d.stl"));
    r = run_fortu("run " + ball + " --ascii -o " + quote(dir / "b.ply"));
    CHECK(r.status == 2);
    CHECK(r.out == "fortu: error: --ascii applies to -o FILE.stl only\n");
    r = run_fortu("run " + ball + " --contour c.svg -o " + quote(dir / "b.stl"));
    CHECK(r.status == 2);
    CHECK(r.out == fmt::format("fortu: error: -o {}: a mesh does not combine with --mimages or --contour (run twice)\n",
                               dir / "b.stl"));
    r = run_fortu("run " + ball + " --size 1 -o " + quote(dir / "b.stl"));
    CHECK(r.status == 2);
    CHECK(r.out == "fortu: error: --size: a mesh needs at least 2 nodes along each axis\n");
    CHECK(dir.entries() == 2);  // nothing written
    // A surface outside the domain: an empty mesh, written, with a warning.
    r = run_fortu("run " + ball + " --domain 2:3,2:3,2:3 --size 9 -o " + quote(dir / "e.stl"));
    CHECK(r.status == 0);
    CHECK(r.out == "fortu: warning: the surface does not cross the domain x [2, 3], y [2, 3], z [2, 3]: the mesh is "
                   "empty\nwrote " + (dir / "e.stl") + " (0 triangles)\n");
}

TEST_CASE("fortu bench --mesh times the mesher per model and size") {
    test::ScratchDir dir;
    const std::string ball = quote(dir.write("ball.fortu", "ARGUMENT X, Y, Z;\nRETURN 0.25 - X*X - Y*Y - Z*Z;\n"));
    const auto r = run_fortu("bench " + ball + " --mesh --sizes 9,17 --repeat 1", ".", true);
    CHECK(r.status == 0);
    std::istringstream lines(r.out);
    std::string header, nine, seventeen;
    std::getline(lines, header);
    std::getline(lines, nine);
    std::getline(lines, seventeen);
    CHECK(header.rfind("model ", 0) == 0);
    CHECK(header.find("triangles") != std::string::npos);
    CHECK(nine.rfind("ball.fortu", 0) == 0);
    CHECK(nine.find(" 9x9x9 ") != std::string::npos);
    CHECK(seventeen.find(" 17x17x17 ") != std::string::npos);
    CHECK(run_fortu("bench " + ball + " --mesh --engines voxel").out ==
          "fortu: error: 'fortu bench --mesh' times the mesher on MODEL... (--sizes, --repeat, --threads)\n");
}
