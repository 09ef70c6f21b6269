// tests/unit/interp_singular_test.cpp — the singular-point criterion of fv-method.md §5.1 on
// its own examples: the points printed exactly (to 1e-6), and K vanishing at them.
#include "interp_test_support.hpp"

#include "interp/singular.hpp"
#include "interp/voxel_engine.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace fortu;
using fortu::test::compile_text;

namespace {

Grid box(const Model& model, int nodes) { return model_grid(model, {nodes, nodes, nodes}); }

std::vector<std::array<double, 2>> points_2d(const std::string& text, int nodes = 401) {
    auto c = compile_text(text);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    std::vector<std::array<double, 2>> out;
    for (const SingularPoint& s : find_singular_points(*c.model, box(*c.model, nodes)))
        out.push_back({s.point[0], s.point[1]});
    return out;
}

void check_points(const std::vector<std::array<double, 2>>& actual,
                  const std::vector<std::array<double, 2>>& expected) {
    REQUIRE(actual.size() == expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        CAPTURE(i);
        CHECK(std::fabs(actual[i][0] - expected[i][0]) <= 1e-6);
        CHECK(std::fabs(actual[i][1] - expected[i][1]) <= 1e-6);
    }
}

}  // namespace

TEST_CASE("(4 - y) & (y - x^2): corners at (±2, 4)") {
    check_points(points_2d("ARGUMENT X(-3, 3), Y(-1, 5);\nRETURN (4 - Y) & (Y - X^2);\n"), {{-2, 4}, {2, 4}});
}

TEST_CASE("the five-sided polygon: five corners; (-7, -3), where R < 0, is rejected") {
    const char* text = "ARGUMENT X(-8, 9), Y(-5, 6);\nRETURN (4 - Y) & (Y + 3) & (7 - X) & (X + 4 - Y) & (Y + X + 3);\n";
    check_points(points_2d(text), {{-3.5, 0.5}, {0, -3}, {0, 4}, {7, -3}, {7, 4}});
    // K vanishes at the rejected point too: it is the R = 0 condition that removes it.
    auto c = compile_text(text);
    const ir::NodeId k = singular_criterion(*c.model);
    CHECK(PointEvaluator(c.model->graph, k)({-7, -3, 0}).value == doctest::Approx(0).epsilon(1e-12));
    CHECK(PointEvaluator(c.model->graph, k)({1, 1, 0}).value > 0);
    CHECK(evaluate_point(*c.model, {-7, -3, 0}, engine_named("voxel")).value < 0);
}

TEST_CASE("the same corners whatever the search grid") {
    check_points(points_2d("ARGUMENT X(-3, 3), Y(-1, 5);\nRETURN (4 - Y) & (Y - X^2);\n", 64), {{-2, 4}, {2, 4}});
}

TEST_CASE("a model without R-operations has no singular points") {
    CHECK(points_2d("ARGUMENT X(-1, 1), Y(-1, 1);\nRETURN 0.5 - X*X - Y*Y;\n").empty());
}

TEST_CASE("the box: every singular point lies on an edge, and every edge is found") {
    auto c = compile_text("ARGUMENT X(-2, 2), Y(-2, 2), Z(-2, 2);\nCONSTANT A = 1, B = 1.2, C = 0.8;\n"
                          "RETURN (A^2 - X^2) & (B^2 - Y^2) & (C^2 - Z^2);\n");
    REQUIRE(c.model);
    const auto points = find_singular_points(*c.model, box(*c.model, 24));
    REQUIRE(points.size() > 12);
    int on_edges_along[3] = {0, 0, 0};
    for (const SingularPoint& s : points) {
        const double x = s.point[0], y = s.point[1], z = s.point[2];
        const bool fx = std::fabs(std::fabs(x) - 1.0) < 1e-9, fy = std::fabs(std::fabs(y) - 1.2) < 1e-9,
                   fz = std::fabs(std::fabs(z) - 0.8) < 1e-9;
        CHECK(fx + fy + fz >= 2);  // on two faces at once: an edge
        CHECK(std::fabs(x) <= 1 + 1e-9);
        CHECK(std::fabs(y) <= 1.2 + 1e-9);
        CHECK(std::fabs(z) <= 0.8 + 1e-9);
        if (fy && fz) ++on_edges_along[0];
        if (fx && fz) ++on_edges_along[1];
        if (fx && fy) ++on_edges_along[2];
    }
    for (int axis = 0; axis < 3; ++axis) CHECK(on_edges_along[axis] >= 4 * 2);  // 4 edges per axis
}

TEST_CASE("Y & (Y - X^2): where the two boundaries touch, one point, not one per seed") {
    // Newton converges only linearly at a tangency and stops up to ~6e-7 from the origin.
    const auto points = points_2d("ARGUMENT X, Y;\nRETURN Y & (Y - X^2);\n");
    REQUIRE(points.size() == 1);
    CHECK(std::fabs(points[0][0]) <= 1e-6);
    CHECK(std::fabs(points[0][1]) <= 1e-6);
}

TEST_CASE("a disc conjoined with its own complement: the singular set is its circle, reported as a curve") {
    auto c = compile_text("ARGUMENT X, Y;\nRETURN (0.5 - X^2 - Y^2) & (X^2 + Y^2 - 0.5);\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const SingularSet set = find_singular_set(*c.model, box(*c.model, 401));
    CHECK(set.points.empty());
    REQUIRE(set.curves.size() == 1);
    CHECK(std::hypot(set.curves[0].point[0], set.curves[0].point[1]) == doctest::Approx(std::sqrt(0.5)).epsilon(1e-9));
    CHECK(set.curves[0].cells > 100);
    // crossing boundaries have no curve
    auto corners = compile_text("ARGUMENT X(-3, 3), Y(-1, 5);\nRETURN (4 - Y) & (Y - X^2);\n");
    CHECK(find_singular_set(*corners.model, box(*corners.model, 401)).curves.empty());
}
