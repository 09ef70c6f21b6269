// tests/unit/interp_toolkit_support.hpp — compiling models that INCLUDE the stdlib, and the
// plain-geometry oracles (point in polygon, distance to a contour) the FLOZ tests compare with,
// written independently of the FORTU code they check.
#pragma once

#include "interp_test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace fortu::test {

struct Point2 {
    double x = 0;
    double y = 0;
};

/// Compiles model text with the source tree's stdlib on the include path (the text's own
/// folder is `path`'s). Fails the test with the diagnostics if it does not compile.
inline Model compile_with_stdlib(const std::string& text, const std::string& path = "test.fortu") {
    CompileOptions options;
    options.include_dirs = {std::string(FORTU_SOURCE_DIR) + "/stdlib"};
    Compiled c = compile_text(text, options, path);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    return std::move(*c.model);
}

/// A FORTU array literal with every digit of each value.
inline std::string fortu_array(const std::vector<double>& values) {
    std::ostringstream s;
    s.precision(17);
    s << '[';
    for (std::size_t i = 0; i < values.size(); ++i) s << (i ? ", " : "") << values[i];
    s << ']';
    return s.str();
}

/// Crossing-number test: is p strictly inside the closed polygon (either orientation)?
inline bool inside_polygon(const std::vector<Point2>& polygon, Point2 p) {
    bool inside = false;
    const std::size_t n = polygon.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const Point2 a = polygon[i], b = polygon[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)) inside = !inside;
    }
    return inside;
}

/// Euclidean distance from p to the segment a-b.
inline double segment_distance(Point2 p, Point2 a, Point2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double len2 = dx * dx + dy * dy;
    const double t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

/// Distance from p to the closed polygon's contour.
inline double contour_distance(const std::vector<Point2>& polygon, Point2 p) {
    double d = INFINITY;
    for (std::size_t i = 0; i < polygon.size(); ++i)
        d = std::min(d, segment_distance(p, polygon[i], polygon[(i + 1) % polygon.size()]));
    return d;
}

/// A square 2D grid of n x n nodes over [lo, hi]².
inline Grid square_grid(double lo, double hi, int n) {
    Grid g;
    g.dims = 2;
    g.x = {lo, hi, n};
    g.y = {lo, hi, n};
    g.z = {0, 0, 1};
    return g;
}

}  // namespace fortu::test
