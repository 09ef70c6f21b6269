// tests/unit/runtime_fv_model_test.cpp — the FV model (fv-method.md §1): planes by formula
// 1.1.3, four/five-term normalisation, orientation, exactness of the local function.
#include "runtime/fv_model.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <functional>

using namespace fortu;

namespace {

Field sample2(int cols, int rows, Axis x, Axis y, const std::function<double(double, double)>& f) {
    Field field;
    field.grid.x = {x.min, x.max, cols};
    field.grid.y = {y.min, y.max, rows};
    field.values.resize(field.grid.points());
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            field.values[field.grid.index(c, r)] = f(field.grid.x_at(c), field.grid.y_at(r));
    return field;
}

Field sample3(int n, const std::function<double(double, double, double)>& f) {
    Field field;
    field.grid.dims = 3;
    field.grid.x = {-1.0, 1.0, n};
    field.grid.y = {-0.5, 1.5, n + 1};
    field.grid.z = {0.0, 2.0, n + 2};
    field.values.resize(field.grid.points());
    const Grid& g = field.grid;
    for (int s = 0; s < g.slices(); ++s)
        for (int r = 0; r < g.rows(); ++r)
            for (int c = 0; c < g.cols(); ++c) field.values[g.index(c, r, s)] = f(g.x_at(c), g.y_at(r), g.z_at(s));
    return field;
}

double norm(const std::array<double, 5>& n, int k) {
    double sum = 0.0;
    for (int i = 0; i < k; ++i) sum += n[i] * n[i];
    return std::sqrt(sum);
}

// The stencil neighbour used by the model (forward, backward at the border).
int forward_or_back(int i, int step, int nodes) { return i + step >= 0 && i + step < nodes ? i + step : i - step; }

}  // namespace

TEST_CASE("fv_plane: formula 1.1.3 on the plane z = x, oriented so n3 > 0") {
    const auto n = fv_plane({0, 0, 0}, {1, 0, 1}, {0, 1, 0});
    const double r = 1.0 / std::sqrt(2.0);
    CHECK(n[0] == doctest::Approx(-r).epsilon(1e-15));
    CHECK(n[1] == 0.0);
    CHECK(n[2] == doctest::Approx(r).epsilon(1e-15));
    CHECK(n[3] == 0.0);

    SUBCASE("the reversed vertex order gives the same oriented plane") {
        CHECK(fv_plane({0, 1, 0}, {1, 0, 1}, {0, 0, 0}) == n);
    }
    SUBCASE("the free term is in the norm") {
        const auto m = fv_plane({0, 0, 1}, {1, 0, 1}, {0, 1, 1});   // z = 1: (0, 0, 1, -1)/√2
        CHECK(m[2] == doctest::Approx(r).epsilon(1e-15));
        CHECK(m[3] == doctest::Approx(-r).epsilon(1e-15));
    }
    SUBCASE("collinear points have no plane") {
        CHECK(std::isnan(fv_plane({0, 0, 0}, {1, 1, 1}, {2, 2, 2})[0]));
    }
    SUBCASE("a non-finite coordinate gives NaN") {
        CHECK(std::isnan(fv_plane({0, 0, NAN}, {1, 0, 1}, {0, 1, 0})[3]));
    }
}

TEST_CASE("FV model of a linear function is exact everywhere (2D)") {
    const auto f = [](double x, double y) { return 0.3 * x - 0.7 * y + 0.2; };
    const Field field = sample2(5, 4, {-1.0, 1.0}, {-0.5, 1.5}, f);
    const FvModel model(field);
    REQUIRE(model.components() == 4);
    // 0.3x − 0.7y − z + 0.2 = 0, flipped so n3 > 0, divided by the four-term norm.
    const double N = std::sqrt(0.3 * 0.3 + 0.7 * 0.7 + 1.0 + 0.2 * 0.2);
    const std::array<double, 4> expected{-0.3 / N, 0.7 / N, 1.0 / N, -0.2 / N};
    for (std::size_t i = 0; i < model.nodes(); ++i) {
        for (int k = 1; k <= 4; ++k) CHECK(model.n(k, i) == doctest::Approx(expected[k - 1]).epsilon(1e-14));
        CHECK(norm(model.node(i), 4) == doctest::Approx(1.0).epsilon(1e-15));
        for (double x : {-2.0, 0.0, 0.37})
            for (double y : {-1.0, 0.5, 3.0}) CHECK(std::abs(model.local_value(i, x, y) - f(x, y)) < 1e-13);
    }
    CHECK(model.image(3).size() == 20);
    CHECK(model.image(3)[7] == model.n(3, 7));
}

TEST_CASE("FV model of a linear function is exact everywhere (3D), n4 > 0") {
    const auto f = [](double x, double y, double z) { return 0.5 * x + 0.25 * y - 0.75 * z + 0.1; };
    const Field field = sample3(3, f);
    const FvModel model(field);
    REQUIRE(model.components() == 5);
    const double N = std::sqrt(0.25 + 0.0625 + 0.5625 + 1.0 + 0.01);
    const std::array<double, 5> expected{-0.5 / N, -0.25 / N, 0.75 / N, 1.0 / N, -0.1 / N};
    for (std::size_t i = 0; i < model.nodes(); ++i) {
        for (int k = 1; k <= 5; ++k) CHECK(model.n(k, i) == doctest::Approx(expected[k - 1]).epsilon(1e-14));
        CHECK(norm(model.node(i), 5) == doctest::Approx(1.0).epsilon(1e-15));
        CHECK(std::abs(model.local_value(i, 0.4, -0.2, 1.1) - f(0.4, -0.2, 1.1)) < 1e-13);
    }
}

TEST_CASE("the local function recovers f at the triangle's vertices (2D, borders included)") {
    const auto f = [](double x, double y) { return 0.4 - (x - 0.3) * (x - 0.3) - (y - 0.3) * (y - 0.3); };
    const Field field = sample2(7, 6, {-1.0, 1.0}, {-1.0, 1.0}, f);
    const FvModel model(field);
    const Grid& g = field.grid;
    double worst = 0.0;
    for (int r = 0; r < g.rows(); ++r)
        for (int c = 0; c < g.cols(); ++c) {
            const std::size_t i = g.index(c, r);
            CHECK(model.n(3, i) > 0.0);
            CHECK(norm(model.node(i), 4) == doctest::Approx(1.0).epsilon(1e-15));
            const int cx = forward_or_back(c, +1, g.cols()), ry = forward_or_back(r, -1, g.rows());
            for (auto [vc, vr] : {std::pair{c, r}, std::pair{cx, r}, std::pair{c, ry}}) {
                const double x = g.x_at(vc), y = g.y_at(vr);
                worst = std::max(worst, std::abs(model.local_value(i, x, y) - field.values[g.index(vc, vr)]));
            }
        }
    CHECK(worst < 1e-12);
}

TEST_CASE("the local function recovers f at the tetrahedron's vertices (3D, borders included)") {
    const auto f = [](double x, double y, double z) { return 1.0 - x * x - y * y * y - std::sin(z); };
    const Field field = sample3(4, f);
    const FvModel model(field);
    const Grid& g = field.grid;
    double worst = 0.0;
    for (int s = 0; s < g.slices(); ++s)
        for (int r = 0; r < g.rows(); ++r)
            for (int c = 0; c < g.cols(); ++c) {
                const std::size_t i = g.index(c, r, s);
                CHECK(model.n(4, i) > 0.0);
                const int cx = forward_or_back(c, +1, g.cols()), ry = forward_or_back(r, -1, g.rows()),
                          sz = forward_or_back(s, +1, g.slices());
                for (auto [vc, vr, vs] : {std::tuple{c, r, s}, std::tuple{cx, r, s}, std::tuple{c, ry, s},
                                          std::tuple{c, r, sz}}) {
                    const double v = model.local_value(i, g.x_at(vc), g.y_at(vr), g.z_at(vs));
                    worst = std::max(worst, std::abs(v - field.values[g.index(vc, vr, vs)]));
                }
            }
    CHECK(worst < 1e-12);
}

TEST_CASE("a non-finite value makes every node whose stencil uses it invalid") {
    Field field = sample2(5, 5, {-1.0, 1.0}, {-1.0, 1.0}, [](double x, double y) { return x + 2 * y; });
    field.values[field.grid.index(2, 2)] = std::nan("");
    const FvModel model(field);
    int invalid = 0;
    for (std::size_t i = 0; i < model.nodes(); ++i) {
        const bool nan = std::isnan(model.n(1, i));
        for (int k = 2; k <= 4; ++k) CHECK(std::isnan(model.n(k, i)) == nan);
        invalid += nan;
    }
    // (2,2) itself, (1,2) whose e_x neighbour it is, (2,3) whose e_y neighbour (row − 1) it is.
    CHECK(invalid == 3);
    CHECK(std::isnan(model.n(1, field.grid.index(1, 2))));
    CHECK(std::isnan(model.n(1, field.grid.index(2, 3))));
    CHECK(std::isnan(model.local_value(field.grid.index(2, 2), 0.0, 0.0)));
}

TEST_CASE("a one-row grid (1-argument model) is constant along Y: n2 = 0") {
    const Field field = sample2(5, 1, {-1.0, 1.0}, {0.0, 0.0}, [](double x, double) { return x * x; });
    const FvModel model(field);
    for (int c = 0; c < 5; ++c) {
        const std::size_t i = field.grid.index(c, 0);
        CHECK(model.n(2, i) == 0.0);
        CHECK(model.n(3, i) > 0.0);
        const int cx = forward_or_back(c, +1, 5);
        CHECK(model.local_value(i, field.grid.x_at(c), 7.0) == doctest::Approx(field.values[i]).epsilon(1e-14));
        CHECK(model.local_value(i, field.grid.x_at(cx), -3.0) ==
              doctest::Approx(field.values[field.grid.index(cx, 0)]).epsilon(1e-14));
    }
}

TEST_CASE("fv_node at the top row and last column uses backward neighbours") {
    // On f = x·y the forward and backward triangles differ; check the top-right corner node
    // against the plane through (x, y), (x − h, y), (x, y − h).
    const Field field = sample2(3, 3, {-1.0, 1.0}, {-1.0, 1.0}, [](double x, double y) { return x * y; });
    const auto n = fv_node(field, 2, 0);
    const auto expected = fv_plane({1, 1, 1}, {0, 1, 0}, {1, 0, 0});
    for (int k = 0; k < 4; ++k) CHECK(n[k] == doctest::Approx(expected[k]).epsilon(1e-15));
    CHECK(n[4] == 0.0);
}

TEST_CASE("local_value dispatches on the number of components") {
    const std::array<double, 4> plane{0.0, 0.0, 1.0, -2.0};             // z = 2
    const std::array<double, 5> hyperplane{0.0, 0.0, 0.0, 2.0, 1.0};   // u = −0.5
    CHECK(local_value(plane, 5.0, 6.0) == 2.0);
    CHECK(local_value(hyperplane, 1.0, 2.0, 3.0) == -0.5);
}

TEST_CASE("fv_node's axis-aligned cross product is formula 1.1.3's plane (§1.2's hyperplane in 3D)") {
    const auto f2 = [](double x, double y) { return std::sin(3 * x) * std::exp(y) - 0.3 * x * y + 1e-3; };
    const Field field = sample2(23, 17, {-2.0, 1.5}, {-1.0, 3.0}, f2);
    const Grid& g = field.grid;
    double worst = 0.0;
    for (int r = 0; r < g.rows(); ++r)
        for (int c = 0; c < g.cols(); ++c) {
            const int cx = forward_or_back(c, +1, g.cols()), ry = forward_or_back(r, -1, g.rows());
            const auto expected = fv_plane({g.x_at(c), g.y_at(r), field.values[g.index(c, r)]},
                                           {g.x_at(cx), g.y_at(r), field.values[g.index(cx, r)]},
                                           {g.x_at(c), g.y_at(ry), field.values[g.index(c, ry)]});
            const auto n = fv_node(field, c, r);
            for (int k = 0; k < 4; ++k) worst = std::max(worst, std::abs(n[k] - expected[k]));
        }
    CHECK(worst < 1e-14);
    const auto f3 = [](double x, double y, double z) { return std::cos(x * y) - z * z * 0.7 + x; };
    const Field field3 = sample3(5, f3);
    const Grid& h = field3.grid;
    worst = 0.0;
    for (int s = 0; s < h.slices(); ++s)
        for (int r = 0; r < h.rows(); ++r)
            for (int c = 0; c < h.cols(); ++c) {
                const int cx = forward_or_back(c, +1, h.cols()), ry = forward_or_back(r, -1, h.rows()),
                          sz = forward_or_back(s, +1, h.slices());
                auto p = [&](int cc, int rr, int ss) {
                    return std::array<double, 4>{h.x_at(cc), h.y_at(rr), h.z_at(ss), field3.values[h.index(cc, rr, ss)]};
                };
                const auto expected = fv_hyperplane(p(c, r, s), p(cx, r, s), p(c, ry, s), p(c, r, sz));
                const auto n = fv_node(field3, c, r, s);
                for (int k = 0; k < 5; ++k) worst = std::max(worst, std::abs(n[k] - expected[k]));
            }
    CHECK(worst < 1e-14);
}

namespace {

/// Every component of every node of `own`, from FvStencil::box over `held`, equals FvModel's
/// bit for bit (the same NaN included); returns the nodes that differ.
std::size_t box_mismatches(const Field& field, const BrickBox& held, const BrickBox& own) {
    const Grid& g = field.grid;
    const FvModel whole(field);
    const FvStencil stencil(g);
    std::vector<double> values(held.points());
    for (int s = held.lo[2]; s <= held.hi[2]; ++s)
        for (int r = held.lo[1]; r <= held.hi[1]; ++r)
            for (int c = held.lo[0]; c <= held.hi[0]; ++c) values[held.local(c, r, s)] = field.values[g.index(c, r, s)];
    const int k = stencil.components();
    std::vector<double> components(k * own.points());
    double* out[5];
    for (int j = 0; j < k; ++j) out[j] = components.data() + j * own.points();
    stencil.box(values.data(), held, own, out);
    std::size_t bad = 0;
    for (int s = own.lo[2]; s <= own.hi[2]; ++s)
        for (int r = own.lo[1]; r <= own.hi[1]; ++r)
            for (int c = own.lo[0]; c <= own.hi[0]; ++c)
                for (int j = 0; j < k; ++j) {
                    const double expected = whole.n(j + 1, g.index(c, r, s)), got = out[j][own.local(c, r, s)];
                    bad += std::memcmp(&expected, &got, sizeof got) != 0;
                }
    return bad;
}

BrickBox box_of(std::array<int, 3> lo, std::array<int, 3> hi) { return BrickBox{lo, hi}; }

}  // namespace

TEST_CASE("a brick's reach: one node more on each forward side (toward smaller rows), backward at the far ends") {
    const Field f = sample3(9, [](double x, double y, double z) { return x * y - z; });   // 9 x 10 x 11 nodes
    const FvStencil stencil(f.grid);
    // Inside: +1 column, −1 row (e_y points to larger Y, the row above), +1 slice.
    CHECK(stencil.reach(box_of({2, 3, 4}, {5, 6, 7})).lo == std::array<int, 3>{2, 2, 4});
    CHECK(stencil.reach(box_of({2, 3, 4}, {5, 6, 7})).hi == std::array<int, 3>{6, 6, 8});
    // At the grid's last column, top row and last slice the stencil reads backward: a brick
    // reaching them needs nothing more, unless it is one node thick there.
    CHECK(stencil.reach(box_of({4, 0, 6}, {8, 3, 10})).lo == std::array<int, 3>{4, 0, 6});
    CHECK(stencil.reach(box_of({4, 0, 6}, {8, 3, 10})).hi == std::array<int, 3>{8, 3, 10});
    CHECK(stencil.reach(box_of({8, 0, 10}, {8, 0, 10})).lo == std::array<int, 3>{7, 0, 9});
    CHECK(stencil.reach(box_of({8, 0, 10}, {8, 0, 10})).hi == std::array<int, 3>{8, 1, 10});
}

TEST_CASE("FvStencil::box over any brick equals the whole field's components bit for bit (3D and 2D)") {
    // Values with cancellation and an invalid point, so any other rounding would show.
    Field f = sample3(9, [](double x, double y, double z) { return std::sin(3 * x) * std::exp(y) - z * z / 3 + 0.1; });
    f.values[f.grid.index(4, 5, 6)] = std::nan("");
    const FvStencil stencil(f.grid);
    const BrickBox boxes[] = {box_of({0, 0, 0}, {8, 9, 10}), box_of({2, 3, 4}, {5, 6, 7}), box_of({0, 0, 0}, {3, 3, 3}),
                              box_of({4, 0, 6}, {8, 3, 10}), box_of({8, 0, 10}, {8, 0, 10}),
                              box_of({0, 9, 0}, {8, 9, 0}), box_of({3, 4, 5}, {5, 6, 7})};
    for (const BrickBox& own : boxes) {
        CAPTURE(own.lo);
        CAPTURE(own.hi);
        CHECK(box_mismatches(f, stencil.reach(own), own) == 0);
        CHECK(box_mismatches(f, box_of({0, 0, 0}, {8, 9, 10}), own) == 0);   // a larger held box: the same
    }
    const Field flat = sample2(13, 7, {-1, 1}, {0, 2}, [](double x, double y) { return std::cos(x * y) - 0.5; });
    const FvStencil plane(flat.grid);
    CHECK(plane.components() == 4);
    for (const BrickBox& own : {box_of({0, 0, 0}, {12, 6, 0}), box_of({5, 2, 0}, {12, 3, 0}), box_of({12, 0, 0}, {12, 0, 0})})
        CHECK(box_mismatches(flat, plane.reach(own), own) == 0);
}
