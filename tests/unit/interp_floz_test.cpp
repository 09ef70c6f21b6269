// tests/unit/interp_floz_test.cpp — stdlib/floz.fortu against plain geometry: FLOZ2 and FLOZ3
// vanish exactly on their simplex, R0 contours keep every segment's zeros, and the signed
// contour (fv-method.md §3.3) is positive exactly inside, for 200 random polygons.
#include "interp_toolkit_support.hpp"

#include "interp/ir_print.hpp"

#include <doctest/doctest.h>

#include <random>

using namespace fortu;
using namespace fortu::test;

namespace {

double at(const Model& model, double x, double y, double z = 0, const Engine& engine = engine_named("voxel")) {
    return evaluate_point(model, {x, y, z}, engine).value;
}

std::string polygon_script(const std::string& function, const std::vector<Point2>& polygon) {
    std::vector<double> xs, ys;
    for (const Point2& p : polygon) {
        xs.push_back(p.x);
        ys.push_back(p.y);
    }
    return "INCLUDE 'floz.fortu';\nARGUMENT X(-1, 1), Y(-1, 1);\nCONSTANT PX = " + fortu_array(xs) +
           ", PY = " + fortu_array(ys) + ";\nRETURN " + function + "(X, Y, PX, PY);\n";
}

/// A random simple polygon: star-shaped around the origin (vertices at increasing angles,
/// random radii), so non-convex in general; some with pairs of vertices a hair apart (very
/// short edges), half of them clockwise.
std::vector<Point2> random_polygon(std::mt19937& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int n = 3 + static_cast<int>(unit(rng) * 18);
    std::vector<double> angles;
    for (int i = 0; i < n; ++i) angles.push_back(unit(rng) * 2 * M_PI);
    std::sort(angles.begin(), angles.end());
    angles.erase(std::unique(angles.begin(), angles.end(), [](double a, double b) { return b - a < 1e-3; }),
                 angles.end());
    std::vector<Point2> polygon;
    const bool short_edges = unit(rng) < 0.4;
    for (double a : angles) {
        const double r = 0.15 + 0.75 * unit(rng);
        polygon.push_back({r * std::cos(a), r * std::sin(a)});
        if (short_edges && unit(rng) < 0.5) {  // a neighbour 0.001 to 0.01 away
            const double d = 0.001 + 0.009 * unit(rng);
            const double a2 = a + d / r * 0.7;
            const double r2 = r + d * 0.7 * (unit(rng) < 0.5 ? 1 : -1);
            polygon.push_back({r2 * std::cos(a2), r2 * std::sin(a2)});
        }
    }
    if (polygon.size() < 3) return random_polygon(rng);
    if (unit(rng) < 0.5) std::reverse(polygon.begin(), polygon.end());
    return polygon;
}

/// Simple polygon check for the generator: no two non-adjacent edges cross or touch.
bool is_simple(const std::vector<Point2>& polygon) {
    const std::size_t n = polygon.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;
            const Point2 a = polygon[i], b = polygon[(i + 1) % n], c = polygon[j], d = polygon[(j + 1) % n];
            const double m = std::min({segment_distance(a, c, d), segment_distance(b, c, d),
                                       segment_distance(c, a, b), segment_distance(d, a, b)});
            auto cross = [](Point2 o, Point2 p, Point2 q) { return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x); };
            const bool crossing = cross(c, d, a) * cross(c, d, b) < 0 && cross(a, b, c) * cross(a, b, d) < 0;
            if (crossing || m < 1e-6) return false;
        }
    return true;
}

}  // namespace

TEST_CASE("FLOZ2 is 0 on its segment and > 0 off it, beyond its ends included") {
    const Model m = compile_with_stdlib("INCLUDE 'floz.fortu'; ARGUMENT X, Y; RETURN FLOZ2(X, Y, -0.5, -0.25, 0.75, 0.5);");
    for (const Engine& engine : exact_engines()) {
        CHECK(at(m, -0.5, -0.25, 0, engine) == 0);
        CHECK(at(m, 0.75, 0.5, 0, engine) == 0);
        for (int k = 1; k < 16; ++k) {
            const double t = k / 16.0;
            CHECK(std::fabs(at(m, -0.5 + 1.25 * t, -0.25 + 0.75 * t, 0, engine)) < 1e-15);
            // off the segment: beside it, beyond either end, on its line
            CHECK(at(m, -0.5 + 1.25 * t - 0.75 * 1e-3, -0.25 + 0.75 * t + 1.25 * 1e-3, 0, engine) > 0);
            CHECK(at(m, -0.5 - 1.25 * t, -0.25 - 0.75 * t, 0, engine) > 0);
            CHECK(at(m, 0.75 + 1.25 * t, 0.5 + 0.75 * t, 0, engine) > 0);
        }
    }
    // the value is the ellipse's distance sum minus the segment's length (S1 eq. 4, corrected)
    CHECK(at(m, 0, 1) == doctest::Approx(std::hypot(0.5, 1.25) + std::hypot(0.75, 0.5) - std::hypot(1.25, 0.75)).epsilon(1e-15));
}

TEST_CASE("FLOZ3 is 0 on its triangle and > 0 off it") {
    // S3's test triangle (1, 0, 1), (-1, 1, -1), (-1, -1, -1)
    const Model m = compile_with_stdlib(
        "INCLUDE 'floz.fortu'; ARGUMENT X, Y, Z; RETURN FLOZ3(X, Y, Z, 1, 0, 1, -1, 1, -1, -1, -1, -1);");
    const double p[3][3] = {{1, 0, 1}, {-1, 1, -1}, {-1, -1, -1}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < 50; ++k) {
        double a = unit(rng), b = unit(rng);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        const double c = 1 - a - b;
        double q[3];
        for (int i = 0; i < 3; ++i) q[i] = a * p[0][i] + b * p[1][i] + c * p[2][i];
        CAPTURE(a);
        CAPTURE(b);
        for (const Engine& engine : exact_engines()) {
            CHECK(std::fabs(at(m, q[0], q[1], q[2], engine)) < 1e-14);
            // off the plane (its normal is (-1, 0, 1))
            CHECK(at(m, q[0] + 2e-3, q[1] + 4e-3, q[2] - 2e-3, engine) > 0);
        }
    }
    for (const auto& v : p) CHECK(std::fabs(at(m, v[0], v[1], v[2])) < 1e-14);
    CHECK(std::fabs(at(m, 0, 0, 0)) < 1e-15);         // (1/2)P1 + (1/4)P2 + (1/4)P3
    CHECK(at(m, 0, 0, 0.5) > 0);
    CHECK(at(m, 3, 0, 3) > 0);                        // in the plane, beyond vertex 1
}

TEST_CASE("R0 contours of FLOZs keep every segment's zeros") {
    const std::vector<Point2> polygon{{-0.8, -0.6}, {0.7, -0.7}, {0.1, -0.1}, {0.6, 0.8}, {-0.5, 0.4}};
    for (const char* function : {"FLOZ_POLYGON", "FLOZ_CONTOUR", "FLOZ_POLYLINE", "FLOZ_CURVE"}) {
        CAPTURE(function);
        const Model m = compile_with_stdlib(polygon_script(function, polygon));
        const bool closed = function == std::string("FLOZ_POLYGON") || function == std::string("FLOZ_CONTOUR");
        const std::size_t segments = closed ? polygon.size() : polygon.size() - 1;
        for (std::size_t i = 0; i < segments; ++i) {
            const Point2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
            for (int k = 0; k <= 8; ++k) {
                const double t = k / 8.0;
                for (const Engine& engine : exact_engines())
                    CHECK(std::fabs(at(m, a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), 0, engine)) < 1e-14);
            }
        }
        // unsigned forms stay positive off the contour
        if (function == std::string("FLOZ_POLYGON") || function == std::string("FLOZ_POLYLINE")) {
            CHECK(at(m, 0, 0.3) > 0);
            CHECK(at(m, 0.9, 0.9) > 0);
        }
    }
}

TEST_CASE("the signed FLOZ contour is positive exactly inside 200 random simple polygons") {
    // Grid points within one grid step of the contour are not judged (fv-method.md §3.3: the
    // sign is that of the nearest FLOZ's line, exact away from the contour's own zeros).
    std::mt19937 rng(20231122);
    const Grid grid = square_grid(-1, 1, 81);
    const double step = grid.x.step();
    int polygons = 0, non_convex = 0, with_short_edges = 0, clockwise = 0;
    std::size_t judged = 0;
    while (polygons < 200) {
        const std::vector<Point2> polygon = random_polygon(rng);
        if (!is_simple(polygon)) continue;
        ++polygons;
        double area2 = 0, shortest = INFINITY;
        int left_turns = 0, right_turns = 0;
        const std::size_t n = polygon.size();
        for (std::size_t i = 0; i < n; ++i) {
            const Point2 a = polygon[i], b = polygon[(i + 1) % n], c = polygon[(i + 2) % n];
            area2 += a.x * b.y - b.x * a.y;
            shortest = std::min(shortest, std::hypot(b.x - a.x, b.y - a.y));
            ((b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x) > 0 ? left_turns : right_turns)++;
        }
        non_convex += left_turns > 0 && right_turns > 0;
        with_short_edges += shortest < 0.01;
        clockwise += area2 < 0;

        const std::string script = polygon_script("FLOZ_CONTOUR", polygon);
        CAPTURE(script);
        const Model m = compile_with_stdlib(script);
        const Field field = evaluate_grid(m, grid, engine_named("voxel"));
        int wrong = 0;
        for (int row = 0; row < grid.rows(); ++row)
            for (int col = 0; col < grid.cols(); ++col) {
                const Point2 p{grid.x_at(col), grid.y_at(row)};
                if (contour_distance(polygon, p) <= step) continue;
                ++judged;
                wrong += (field.values[grid.index(col, row)] > 0) != inside_polygon(polygon, p);
            }
        CHECK(wrong == 0);
    }
    MESSAGE("polygons: ", polygons, ", non-convex ", non_convex, ", with edges < 0.01: ", with_short_edges,
            ", clockwise ", clockwise, "; grid points judged: ", judged);
    CHECK(non_convex >= 100);
    CHECK(with_short_edges >= 30);
    CHECK(clockwise >= 60);
}

TEST_CASE("FLOZ_CONTOUR's sign does not depend on the contour's orientation") {
    std::vector<Point2> polygon{{-0.8, -0.6}, {0.7, -0.7}, {0.1, -0.1}, {0.6, 0.8}, {-0.5, 0.4}};
    const Model ccw = compile_with_stdlib(polygon_script("FLOZ_CONTOUR", polygon));
    std::reverse(polygon.begin(), polygon.end());
    const Model cw = compile_with_stdlib(polygon_script("FLOZ_CONTOUR", polygon));
    for (Point2 p : std::vector<Point2>{{0, -0.4}, {0.5, 0.2}, {-0.6, 0}, {0.9, 0.9}, {0.4, 0.6}}) {
        CAPTURE(p.x);
        CAPTURE(p.y);
        CHECK((at(ccw, p.x, p.y) > 0) == inside_polygon(polygon, p));
        // R0 is not associative, so the values differ with the order of the edges; the signs do not
        CHECK((at(cw, p.x, p.y) > 0) == (at(ccw, p.x, p.y) > 0));
    }
}

TEST_CASE("FLOZ_CONTOUR's cost stays linear in the number of segments") {
    // A regular N-gon: the voxel engine's operations grow by the same amount per segment.
    auto nodes = [](int n) {
        std::vector<Point2> polygon;
        for (int k = 0; k < n; ++k)  // turned by 0.1 so that no coordinate is 0 (folded away)
            polygon.push_back({0.8 * std::cos(0.1 + 2 * M_PI * k / n), 0.8 * std::sin(0.1 + 2 * M_PI * k / n)});
        return ir_stats(compile_with_stdlib(polygon_script("FLOZ_CONTOUR", polygon))).operations;
    };
    const std::size_t n16 = nodes(16), n32 = nodes(32), n64 = nodes(64);
    CHECK(n64 - n32 == 2 * (n32 - n16));
    CHECK((n32 - n16) / 16 <= 40);  // per segment: FLOZ2, R0, distance, side, arg-min
}

TEST_CASE("a repeated vertex (a zero-length edge) is skipped: the values equal the contour's without it") {
    // Many users close a polygon by writing its first vertex again; the edge between the
    // copies has no direction, which made every node NaN.
    const Model closed = compile_with_stdlib("INCLUDE 'floz.fortu'; ARGUMENT X(-5,5), Y(-5,5); "
                                             "CONSTANT PX=[-3,3,3,-3,-3]; CONSTANT PY=[-3,-3,3,3,-3]; "
                                             "RETURN FLOZ_CONTOUR(X,Y,PX,PY);");
    const Field field = evaluate_grid(closed, square_grid(-5, 5, 41), engine_named("voxel"));
    CHECK(std::count_if(field.values.begin(), field.values.end(), [](double v) { return !std::isfinite(v); }) == 0);

    const std::vector<Point2> square{{-3, -3}, {3, -3}, {3, 3}, {-3, 3}};
    const std::vector<Point2> closing_repeat{{-3, -3}, {3, -3}, {3, 3}, {-3, 3}, {-3, -3}, {-3, -3}};
    const std::vector<Point2> written_twice{{-3, -3}, {3, -3}, {3, -3}, {3, 3}, {3, 3}, {3, 3}, {-3, 3}};
    for (const char* function : {"FLOZ_CONTOUR", "FLOZ_CONTOUR_S1", "FLOZ_POLYGON", "FLOZ_POLYLINE", "FLOZ_CURVE"}) {
        CAPTURE(function);
        const Model plain = compile_with_stdlib(polygon_script(function, square));
        const bool closed_contour = function != std::string("FLOZ_POLYLINE") && function != std::string("FLOZ_CURVE");
        std::vector<Model> repeats{compile_with_stdlib(polygon_script(function, written_twice))};
        if (closed_contour) repeats.push_back(compile_with_stdlib(polygon_script(function, closing_repeat)));
        for (const Model& repeated : repeats)
            for (const Engine& engine : exact_engines())
                for (double x = -5; x <= 5; x += 0.625)
                    for (double y = -5; y <= 5; y += 0.625) {
                        CAPTURE(x);
                        CAPTURE(y);
                        const double expected = at(plain, x, y, 0, engine);
                        CHECK(std::isfinite(expected));
                        CHECK(at(repeated, x, y, 0, engine) == expected);
                    }
    }
}
