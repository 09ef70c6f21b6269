// tests/unit/interp_toolkit_test.cpp — the modelling toolkit as a whole: every example runs
// in both engines with equal values, S1 Fig. 3a's two forms draw the same contour, long FOR
// loops lower quickly, and the rfunc, shapes, perturb and singular libraries compute what
// their formulas say (fv-method.md §2.4, §5).
#include "test_support.hpp"
#include "interp_toolkit_support.hpp"

#include "interp/classic_cost.hpp"
#include "interp/ir_print.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

using namespace fortu;
using namespace fortu::test;

namespace {


Model compile_example(const std::string& name) {
    const std::filesystem::path path = std::filesystem::path(FORTU_SOURCE_DIR) / "examples" / name;
    return compile_with_stdlib(read_file(path), path.string());
}

double at(const Model& model, double x, double y, double z = 0, const Engine& engine = engine_named("voxel")) {
    return evaluate_point(model, {x, y, z}, engine).value;
}

/// The model's own box, `n` nodes per axis.
Grid example_grid(const Model& model, int n) {
    Grid g;
    g.dims = model.dims();
    Axis* axes[3] = {&g.x, &g.y, &g.z};
    for (int a = 0; a < 3; ++a) {
        if (model.ranges[a]) *axes[a] = {model.ranges[a]->min, model.ranges[a]->max, n};
        else *axes[a] = {-1, 1, n};
    }
    if (g.dims == 2) g.z = {0, 0, 1};
    return g;
}

// The nine vertices of examples/s1_fig3a_formula.fortu and s1_fig3a_floz.fortu.
const std::vector<Point2> kFig3a{{-4, -3}, {4, -3}, {2.5, -0.5}, {4, 3}, {2, 1.2},
                                 {0, 0.5}, {-1, 2}, {-4, 3}, {-2, 0}};

}  // namespace

TEST_CASE("every example runs in both engines with equal values") {
    // The whole small grid is compared when the classic estimate fits the test's budget, a
    // few points otherwise; R0 chains over many FLOZs expand to 2^segments in the classic
    // engine (the papers' point), so for those only the voxel engine runs, and the test
    // names them, so an example that silently stops being comparable fails.
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FORTU_SOURCE_DIR) / "examples"))
        if (e.path().extension() == ".fortu") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    REQUIRE(files.size() >= 20);
    std::set<std::string> whole_grid, at_points, voxel_only;
    for (const auto& file : files) {
        const std::string name = file.filename().string();
        CAPTURE(name);
        const Model m = compile_example(name);
        const Grid grid = example_grid(m, m.dims() == 3 ? 12 : 32);
        const Field voxel = evaluate_grid(m, grid, engine_named("voxel"));
        std::size_t positive = 0, negative = 0;
        for (double v : voxel.values) (v > 0 ? positive : negative) += v != 0;
        CHECK(voxel.invalid_count() == 0);
        CHECK(positive > 0);   // every example draws something, and not everything
        CHECK(negative > 0);
        const double per_point = classic_operations_per_point(m.graph, m.root);
        if (per_point * double(grid.points()) <= 2e8) {
            const Field classic = evaluate_grid(m, grid, engine_named("classic"));
            std::size_t different = 0;
            for (std::size_t i = 0; i < grid.points(); ++i) different += classic.values[i] != voxel.values[i];
            CHECK(different == 0);
            whole_grid.insert(name);
        } else if (per_point <= 2e7) {
            for (int s = 0; s < 4; ++s) {
                const double t = (s + 0.5) / 4;
                const int col = static_cast<int>(t * (grid.cols() - 1));
                const int row = static_cast<int>((1 - t) * (grid.rows() - 1));
                const int slice = static_cast<int>(t * (grid.slices() - 1));
                const std::array<double, 3> p{grid.x_at(col), grid.y_at(row), grid.z_at(slice)};
                CHECK(evaluate_point(m, p, engine_named("classic")).value == voxel.values[grid.index(col, row, slice)]);
                CHECK(evaluate_point(m, p, engine_named("voxel")).value == voxel.values[grid.index(col, row, slice)]);
            }
            at_points.insert(name);
        } else {
            voxel_only.insert(name);
        }
    }
    MESSAGE("whole grid: ", whole_grid.size(), ", at points: ", at_points.size(), ", voxel only: ", voxel_only.size());
    CHECK(voxel_only == std::set<std::string>{"floz3_sphere80.fortu", "s1_fig4a_arcs.fortu", "s1_fig4b_inner.fortu",
                                              "s1_fig7_bezier.fortu", "s1_fig8_predicate.fortu"});
}

TEST_CASE("S1 Fig. 3a: formula (3) and the FLOZ-construction have the same sign at 800x800") {
    const Model formula = compile_example("s1_fig3a_formula.fortu");
    const Model floz = compile_example("s1_fig3a_floz.fortu");
    const Grid grid = example_grid(formula, 800);
    REQUIRE(grid.x.min == -5);
    REQUIRE(grid.y.max == 5);
    const Field a = evaluate_grid(formula, grid, engine_named("voxel"));
    const Field b = evaluate_grid(floz, grid, engine_named("voxel"));
    const double step = std::max(grid.x.step(), grid.y.step());
    std::size_t judged = 0, different = 0, outside_polygon_test = 0;
    for (int row = 0; row < grid.rows(); ++row)
        for (int col = 0; col < grid.cols(); ++col) {
            const Point2 p{grid.x_at(col), grid.y_at(row)};
            if (contour_distance(kFig3a, p) <= step) continue;
            ++judged;
            const bool inside = a.values[grid.index(col, row)] > 0;
            different += inside != (b.values[grid.index(col, row)] > 0);
            outside_polygon_test += inside != inside_polygon(kFig3a, p);
        }
    CHECK(judged > 600000);
    CHECK(different == 0);
    CHECK(outside_polygon_test == 0);
}

TEST_CASE("a 1000-step FOR loop unrolls into a chain of 1000 R-operations") {
    const std::string text =
        "ARGUMENT X, Y;\n"
        "VARIABLE W = X;\n"
        "FOR I = 1, 1000\n"
        "  W = W & (Y - I/1000);\n"
        "END FOR\n"
        "RETURN W;\n";
    const auto start = std::chrono::steady_clock::now();
    const Compiled c = compile_text(text);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    REQUIRE(c.model);
    const IrStats stats = ir_stats(*c.model);
    // X, Y, the constants I/1000 (1000), Y - I/1000 (1000) and the R0 conjunctions (1000)
    CHECK(stats.nodes == 3002);
    CHECK(stats.operations == 2000);
    CHECK(stats.depth == 1002);  // 1000 conjunctions, a subtraction, a leaf
    MESSAGE("1000-step FOR loop lowered in ", seconds, " s");  // reported, never asserted
}

TEST_CASE("rfunc: the R-systems as functions agree with & and | under RSYSTEM") {
    const std::string head = "INCLUDE 'rfunc.fortu'; ARGUMENT X, Y; ";
    for (const Engine& engine : exact_engines()) {
        const Model r0 = compile_with_stdlib(head + "RETURN R0_AND(X, Y) - (X & Y) + 10 * (R0_OR(X, Y) - (X | Y));");
        CHECK(at(r0, 0.3, -0.7, 0, engine) == 0);
        const Model ra = compile_with_stdlib(head + "RSYSTEM ALPHA = 0.5; RETURN RA_AND(X, Y, 0.5) - (X & Y);");
        CHECK(at(ra, 0.3, -0.7, 0, engine) == doctest::Approx(0).epsilon(1e-15));
        const Model r1 = compile_with_stdlib(head + "RETURN R1_AND(X, Y) + 10 * R1_OR(X, Y);");
        CHECK(at(r1, 0.3, -0.7, 0, engine) == -0.7 + 10 * 0.3);
    }
    const Model rp = compile_with_stdlib(head + "RETURN RP_AND(X, Y, 2) - R0_AND(X, Y);");
    CHECK(at(rp, 0.3, 0.4) == doctest::Approx(0).epsilon(1e-15));
    const Model blend = compile_with_stdlib(head + "RETURN BLEND_AND(X, Y, 0.5, 1, 2);");
    CHECK(at(blend, 3, 4) == doctest::Approx(3 + 4 - 5 + 0.5 / (1 + 9 + 4)).epsilon(1e-15));
}

TEST_CASE("shapes: half-planes are positive on the left, shapes positive inside") {
    const std::string head = "INCLUDE 'shapes.fortu'; ARGUMENT X, Y; ";
    const Model h = compile_with_stdlib(head + "RETURN HALFPLANE(X, Y, 0, 0, 3, 4);");
    CHECK(at(h, -4, 3) == doctest::Approx(5));   // the distance, left of (0,0) -> (3,4)
    CHECK(at(h, 4, -3) == doctest::Approx(-5));
    const Model square = compile_with_stdlib(head + "CONSTANT PX = [-1, 1, 1, -1], PY = [-1, -1, 1, 1]; "
                                                    "RETURN CONVEX_POLYGON(X, Y, PX, PY);");
    CHECK(at(square, 0, 0) > 0);
    CHECK(at(square, 0.99, 0.5) > 0);
    CHECK(at(square, 1.01, 0.5) < 0);
    CHECK(at(square, 1, 0.5) == 0);
    const Model rect = compile_with_stdlib(head + "RETURN RECTANGLE_XY(X, Y, 2, 1, -1, 3);");
    CHECK(at(rect, 0, 2) > 0);
    CHECK(at(rect, 2.5, 2) < 0);
    const Model disc = compile_with_stdlib(head + "RETURN DISC(ROTATE_X(X, Y, PI/2), ROTATE_Y(X, Y, PI/2), 1, 0, 0.5);");
    CHECK(at(disc, 0, 1) == doctest::Approx(0.25));  // (0, 1) rotated by -pi/2 is (1, 0)
}

TEST_CASE("perturb: analytic MAX(Q, 0)^K, K = 3 by default") {
    const std::string head = "INCLUDE 'perturb.fortu'; ARGUMENT X, Y; ";
    const Model k3 = compile_with_stdlib(head + "RETURN PERTURB(-Y, 1 - X^2 - Y^2);");
    const Model k2 = compile_with_stdlib(head + "RETURN PERTURB_K(-Y, 1 - X^2 - Y^2, 2);");
    for (const Engine& engine : exact_engines()) {
        CHECK(at(k3, 0.5, 0.25, 0, engine) == doctest::Approx(-0.25 + std::pow(1 - 0.25 - 0.0625, 3)));
        CHECK(at(k2, 0.5, 0.25, 0, engine) == doctest::Approx(-0.25 + std::pow(1 - 0.25 - 0.0625, 2)));
        CHECK(at(k3, 2, 0.25, 0, engine) == -0.25);  // Q < 0: the base alone
    }
    // C² join at Q = 0 for K = 3: the value's gradient is continuous there (the bump adds 0)
    const PointValue edge = evaluate_point(k3, {1, 0, 0}, engine_named("voxel"));
    CHECK(edge.gradient[0] == 0);
}

TEST_CASE("perturb: BILINEAR is Vyatkin's bilinear interpolation of the table") {
    // S8 (fv-method.md §5.2): f0 = (1-s)T[mv][mu] + sT[mv][mu+1], f1 likewise on row mv+1,
    // h = f0 + (f1 - f0)(v - mv), written out here on its own.
    const std::vector<double> table{0.5, -1, 2, 0.25, 3, 1, -0.5, 4, 1.5, 2.5, 0, -2};  // 3 rows of 4
    const Model m = compile_with_stdlib("INCLUDE 'perturb.fortu'; ARGUMENT U, V; CONSTANT T = " +
                                        fortu_array(table) + "; RETURN BILINEAR(U, V, T, 4);");
    auto reference = [&](double u, double v) {
        const int mu = std::min(static_cast<int>(std::floor(u)), 2), mv = std::min(static_cast<int>(std::floor(v)), 1);
        const double s = u - mu;
        auto t = [&](int row, int col) { return table[row * 4 + col]; };
        const double f0 = (1 - s) * t(mv, mu) + s * t(mv, mu + 1);
        const double f1 = (1 - s) * t(mv + 1, mu) + s * t(mv + 1, mu + 1);
        return f0 + (f1 - f0) * (v - mv);
    };
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0, 3), v(0, 2);
    for (int k = 0; k < 100; ++k) {
        const double pu = u(rng), pv = v(rng);
        CAPTURE(pu);
        CAPTURE(pv);
        CHECK(at(m, pu, pv) == doctest::Approx(reference(pu, pv)).epsilon(1e-14));
    }
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) CHECK(at(m, col, row) == table[row * 4 + col]);
    CHECK(at(m, -1, 1) == 0);  // one cell beyond the table the hats have died out
    CHECK(at(m, 2, 3.5) == 0);
}

TEST_CASE("perturb: HEIGHTMAP_PLANE raises the plane by the table over its rectangle") {
    const Model m = compile_with_stdlib(
        "INCLUDE 'perturb.fortu'; ARGUMENT X, Y, Z; CONSTANT T = [0, 0, 0, 0, 1, 0, 0, 0, 0];"
        "RETURN HEIGHTMAP_PLANE(X, Y, Z, 0.5, -1, -1, 1, 1, T, 3);");
    CHECK(at(m, 0, 0, 1.5) == 0);      // the peak: Z0 + 1
    CHECK(at(m, 0, 0, 1) > 0);         // under it
    CHECK(at(m, 0.5, 0.5, 0.75) == 0); // halfway to the corner node: h = 1/4
    CHECK(at(m, 3, 3, 0.5) == 0);      // outside: the plane itself
    CHECK(at(m, 3, 3, 0.4) > 0);
    CHECK(at(m, 3, 3, 0.6) < 0);
}

TEST_CASE("perturb: HEIGHTMAP_PLANE_CUT is S8 eq. 6: F & (h - threshold) & DP") {
    // Written out on its own: the R0 conjunction a + b - sqrt(a² + b²), folded left, of the
    // plane's F = Z0 + h - Z, the threshold test h - THRESHOLD and the rectangle DP.
    const std::vector<double> table{0, 0.2, 0, 0.6, 1, 0.4, 0, 0.3, 0};   // 3 rows of 3
    const double z0 = 0.5, x1 = -1, y1 = -0.5, x2 = 1.5, y2 = 1, threshold = 0.25;
    const Model m = compile_with_stdlib("INCLUDE 'perturb.fortu'; ARGUMENT X, Y, Z; CONSTANT T = " +
                                        fortu_array(table) +
                                        "; RETURN HEIGHTMAP_PLANE_CUT(X, Y, Z, 0.5, -1, -0.5, 1.5, 1, T, 3, 0.25);");
    auto r0 = [](double a, double b) { return a + b - std::sqrt(a * a + b * b); };
    auto height = [&](double x, double y) {   // S8's bilinear interpolation, inside DP
        const double u = (x - x1) / (x2 - x1) * 2, v = (y2 - y) / (y2 - y1) * 2;
        const int mu = std::min(static_cast<int>(std::floor(u)), 1), mv = std::min(static_cast<int>(std::floor(v)), 1);
        const double s = u - mu;
        auto t = [&](int row, int col) { return table[row * 3 + col]; };
        const double f0 = (1 - s) * t(mv, mu) + s * t(mv, mu + 1), f1 = (1 - s) * t(mv + 1, mu) + s * t(mv + 1, mu + 1);
        return f0 + (f1 - f0) * (v - mv);
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> px(x1, x2), py(y1, y2), pz(0, 2);
    for (int k = 0; k < 100; ++k) {
        const double x = px(rng), y = py(rng), z = pz(rng), h = height(x, y);
        const double dp = r0(r0(r0(x - x1, x2 - x), y - y1), y2 - y);
        CAPTURE(x);
        CAPTURE(y);
        CAPTURE(z);
        CHECK(at(m, x, y, z) == doctest::Approx(r0(r0(z0 + h - z, h - threshold), dp)).epsilon(1e-12));
    }
    CHECK(at(m, -0.25, 0.75, 0.5) > 0);    // h = 0.45 above the threshold, under the surface
    CHECK(at(m, 1.25, 0.75, 0.5) < 0);     // h = 0.1 under the threshold: cut away though Z < Z0 + h
    CHECK(at(m, 2, 0.25, 0) < 0);          // outside DP: cut away though under the plane
    CHECK(at(m, 0.25, 0.25, 1.5) == 0);    // the peak node, h = 1: on the surface
}

TEST_CASE("singular: the criterion vanishes exactly at the corners (fv-method.md §5.1)") {
    const Model m = compile_with_stdlib(
        "INCLUDE 'singular.fortu'; ARGUMENT X, Y;\n"
        "VARIABLE W1 = 4 - Y, W2 = Y + 3, W3 = 7 - X, W4 = X + 4 - Y, W5 = Y + X + 3;\n"
        "VARIABLE P1 = W1 & W2, P2 = P1 & W3, P3 = P2 & W4, R = P3 & W5;\n"
        "VARIABLE K = SINGULAR_K(W1, W2) * SINGULAR_K(P1, W3) * SINGULAR_K(P2, W4) * SINGULAR_K(P3, W5);\n"
        "RETURN SINGULAR_CRITERION(R, K);\n");
    for (Point2 p : std::vector<Point2>{{-3.5, 0.5}, {0, 4}, {7, 4}, {7, -3}, {0, -3}}) {
        CAPTURE(p.x);
        CAPTURE(p.y);
        CHECK(at(m, p.x, p.y) == 0);
        CHECK(at(m, p.x + 1e-3, p.y) > 0);
    }
    CHECK(at(m, -7, -3) == 196);  // K = 0 there, but R = -14: no corner
    CHECK(at(m, 3, 4) > 0);       // on an edge, not at a corner
    const Model k1 = compile_with_stdlib("INCLUDE 'singular.fortu'; ARGUMENT X, Y; RETURN SINGULAR_K(4 - Y, Y - X^2);");
    CHECK(at(k1, 2, 4) == 0);
    CHECK(at(k1, -2, 4) == 0);
    CHECK(at(k1, 0, 4) == 16);
}

TEST_CASE("FLOZ3_MESH: the 80-triangle sphere is positive inside, zero on the mesh, negative outside") {
    const Model m = compile_example("floz3_sphere80.fortu");
    CHECK(at(m, 0, 0, 0) > 0);
    CHECK(at(m, 0.5, -0.3, 0.2) > 0);
    CHECK(at(m, 1.1, 0, 0) < 0);
    CHECK(at(m, 0.7, 0.7, 0.7) < 0);
    // well inside (below the faces' least distance from the centre, 0.934) or outside the
    // unit sphere, the nearest-FLOZ3 sign is right
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coordinate(-1.25, 1.25);
    int judged = 0, wrong = 0;
    for (int k = 0; k < 400; ++k) {
        const double x = coordinate(rng), y = coordinate(rng), z = coordinate(rng);
        const double r = std::sqrt(x * x + y * y + z * z);
        if (r > 0.9 && r < 1.01) continue;
        ++judged;
        wrong += (at(m, x, y, z) > 0) != (r < 0.9);
    }
    CHECK(judged > 300);
    CHECK(wrong == 0);
    // the icosahedron's vertices (0, ±1, ±T)/|.| lie on the mesh
    const double t = (1 + std::sqrt(5.0)) / 2, s = std::sqrt(1 + t * t);
    CHECK(std::fabs(at(m, 0, 1 / s, t / s)) < 1e-12);
    CHECK(std::fabs(at(m, 0, -1 / s, -t / s)) < 1e-12);
}

// IMAGE's semantics are tested in memory (interp_include_test.cpp); this one is the disk
// loader's: a real file OpenImageIO cannot decode.
TEST_CASE("IMAGE of a file that is no picture is a model error naming the file") {
    CompileOptions options;
    Compiled c = compile_text("ARGUMENT X, Y; CONSTANT T = IMAGE('floz.fortu'); RETURN X + T(1);", options,
                              std::string(FORTU_SOURCE_DIR) + "/stdlib/model.fortu");
    CHECK(!c.model);
    REQUIRE(c.sink.diagnostics().size() == 1);
    CHECK(c.sink.diagnostics()[0].message.rfind("cannot read image 'floz.fortu': ", 0) == 0);
}
