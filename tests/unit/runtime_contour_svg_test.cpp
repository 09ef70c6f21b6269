// tests/unit/runtime_contour_svg_test.cpp — the SVG contour drawn by librsvg (rsvg-convert,
// Debian librsvg2-bin) lies on the PNG's contour pixels: the stroke is in pixels of the same
// picture, not world units that only browsers honour through vector-effect.
#include "test_support.hpp"
#include "runtime/image_io.hpp"
#include "runtime/output.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <functional>

using namespace fortu;

namespace {

using fortu::test::ScratchDir;

double r_or(double a, double b) { return a + b + std::sqrt(a * a + b * b); }
double r_and(double a, double b) { return a + b - std::sqrt(a * a + b * b); }

Field sample(int cols, int rows, Axis x, Axis y, const std::function<double(double, double)>& fn) {
    Field f;
    f.grid.x = {x.min, x.max, cols};
    f.grid.y = {y.min, y.max, rows};
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) f.values.push_back(fn(f.grid.x_at(c), f.grid.y_at(r)));
    return f;
}

/// A gear (12 teeth, a hole), the model that rsvg drew as a black square.
double gear(double x, double y) {
    const double r2 = x * x + y * y;
    const double teeth = 0.05 * (std::cos(12 * std::atan2(y, x)) - 0.2);
    return r_and(r_or(0.36 - r2, r_and(0.49 - r2, teeth)), r2 - 0.04);
}

/// Pixels marked in a cols x rows mask.
struct Mask {
    int cols = 0, rows = 0;
    std::vector<bool> on;
    bool at(int c, int r) const { return c >= 0 && r >= 0 && c < cols && r < rows && on[std::size_t(r) * cols + c]; }
    std::size_t count() const { return static_cast<std::size_t>(std::count(on.begin(), on.end(), true)); }
};

Mask read_mask(const std::string& path, const std::function<bool(const float*, int)>& marked) {
    std::string error;
    const auto image = read_image(path, error);
    REQUIRE_MESSAGE(image, error);
    Mask m{image->cols, image->rows, {}};
    const int channels = static_cast<int>(image->channels.size());
    for (std::size_t p = 0; p < std::size_t(m.cols) * m.rows; ++p)
        m.on.push_back(marked(&image->pixels[p * channels], channels));
    return m;
}

/// The share of `a`'s pixels with a pixel of `b` within 1.5 px (the 3x3 block around it).
double share_near(const Mask& a, const Mask& b) {
    std::size_t near = 0;
    for (int r = 0; r < a.rows; ++r)
        for (int c = 0; c < a.cols; ++c) {
            if (!a.at(c, r)) continue;
            bool found = false;
            for (int dr = -1; dr <= 1 && !found; ++dr)
                for (int dc = -1; dc <= 1 && !found; ++dc) found = b.at(c + dc, r + dr);
            near += found;
        }
    return a.count() ? double(near) / double(a.count()) : 0.0;
}

/// Writes the PNG and SVG of `f`, draws the SVG with rsvg-convert and checks both ways that
/// ≥ 95% of one's line pixels lie within 1.5 px of the other's.
void check_svg_matches_png(const Field& f) {
    ScratchDir dir;
    write_field(f, dir / "f.png");
    write_field(f, dir / "f.svg");
    const std::string command =
        fmt::format("rsvg-convert '{}' -o '{}' 2>&1", dir / "f.svg", dir / "svg.png");
    REQUIRE_MESSAGE(std::system(command.c_str()) == 0, "rsvg-convert (Debian librsvg2-bin) must be installed");
    // PNG contour pixels are exactly black; the SVG's stroke is black on a transparent
    // background, antialiased: a pixel at least half covered counts.
    const Mask png = read_mask(dir / "f.png", [](const float* p, int) { return p[0] == 0 && p[1] == 0 && p[2] == 0; });
    const Mask svg = read_mask(dir / "svg.png", [](const float* p, int n) { return n == 4 && p[3] >= 0.5f; });
    REQUIRE(svg.cols == png.cols);
    REQUIRE(svg.rows == png.rows);
    CHECK(png.count() > 100);
    // A stroke in world units came out as a black square (every pixel) or a 120 px band.
    CHECK(svg.count() < 3 * png.count());
    CHECK(share_near(svg, png) >= 0.95);
    CHECK(share_near(png, svg) >= 0.95);
}

}  // namespace

TEST_CASE("svg contour: drawn by rsvg-convert, it lies on the PNG's contour pixels") {
    SUBCASE("the gear, square") { check_svg_matches_png(sample(256, 256, {-0.8, 0.8}, {-0.8, 0.8}, gear)); }
    SUBCASE("a wide domain, unequal steps") {
        // A ring over [-5, 5] x [-2, 2] on 300 x 160 nodes: x and y steps differ.
        check_svg_matches_png(sample(300, 160, {-5, 5}, {-2, 2}, [](double x, double y) {
            const double r2 = x * x / 16 + y * y / 2;
            return r_and(1 - r2, r2 - 0.3);
        }));
    }
}

TEST_CASE("svg contour: a pixel viewBox, world box in metadata, no vector-effect") {
    ScratchDir dir;
    write_field(sample(40, 20, {-2, 2}, {0, 1}, [](double x, double y) { return 0.25 - x * x - (y - 0.5) * (y - 0.5); }),
                dir / "c.svg");
    const std::string svg = dir.read("c.svg");
    CHECK(svg.find("width=\"40\" height=\"20\" viewBox=\"0 0 40 20\"") != std::string::npos);
    CHECK(svg.find("<fortu-domain xmlns=\"urn:fortu:domain\" x0=\"-2\" x1=\"2\" y0=\"0\" y1=\"1\"") != std::string::npos);
    CHECK(svg.find("stroke-width=\"1.5\"") != std::string::npos);
    CHECK(svg.find("vector-effect") == std::string::npos);
    CHECK(svg.find("transform") == std::string::npos);
}
