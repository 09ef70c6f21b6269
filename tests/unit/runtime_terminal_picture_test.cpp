// tests/unit/runtime_terminal_picture_test.cpp — the terminal picture of `fortu repl :show`:
// which cell shows what in ASCII, and the exact escape sequences of the half blocks.
#include "runtime/picture.hpp"
#include "runtime/terminal_picture.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <limits>

using namespace fortu;

namespace {

Field field_of(int cols, int rows, std::vector<double> values) {
    Field f;
    f.grid.dims = 2;
    f.grid.x.nodes = cols;
    f.grid.y.nodes = rows;
    f.values = std::move(values);
    return f;
}

std::string sgr(const char* which, Rgb8 c) { return fmt::format("\x1b[{};2;{};{};{}m", which, c.r, c.g, c.b); }

}  // namespace

TEST_CASE("ASCII: two pixels per cell; contour, then invalid, then the upper pixel's sign") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // Contour pixels (render_slice's rule): (0,1) and (0,2) meet across the sign change, and
    // (1,2) lies under the -1. The last row is odd: its cells have no lower pixel.
    const Field f = field_of(3, 3, {1, 1, -1,
                                    1, 1, 1,
                                    nan, 1, 1});
    CHECK(terminal_picture(f, 0, false) == "#**\n?##\n");
    // Outside only: dots.
    CHECK(terminal_picture(field_of(2, 2, {-1, -2, -3, -4}), 0, false) == "..\n");
}

TEST_CASE("colour: upper pixel as foreground, lower as background, reset per line") {
    const std::vector<double> values{2, -1};
    const Field f = field_of(1, 2, values);
    const Rgb8 inside = value_colour(2, colour_scale(values));
    CHECK(inside == kInsideFar);
    // The -1 touches the larger 2 across the sign change: it is the contour.
    CHECK(terminal_picture(f, 0, true) == sgr("38", inside) + sgr("48", kContourColour) + "\u2580\x1b[0m\n");
    // An odd last row keeps the terminal's background under its half block.
    const Field single = field_of(1, 1, {0.5});
    CHECK(terminal_picture(single, 0, true) ==
          sgr("38", value_colour(0.5, colour_scale(single.values))) + "\x1b[49m\u2580\x1b[0m\n");
}

TEST_CASE("a 3D field shows the requested slice") {
    Field f = field_of(2, 2, {-1, -1, -1, -1, 1, 2, 3, 4});
    f.grid.dims = 3;
    f.grid.z.nodes = 2;
    CHECK(terminal_picture(f, 0, false) == "..\n");
    CHECK(terminal_picture(f, 1, false) == "##\n");
}
