// tests/unit/runtime_picture_legend_test.cpp — the picture's scale choices (--scale), its
// iso-levels (--levels) and its legend (--legend), on fields whose values are known at every
// pixel, written as PNG and read back.
#include "test_support.hpp"
#include "runtime/bitmap_font.hpp"
#include "runtime/image_io.hpp"
#include "runtime/output.hpp"
#include "runtime/picture.hpp"
#include "runtime/picture_legend.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>

using namespace fortu;

namespace {

using fortu::test::ScratchDir;

// x over [-1, 1] on 17 columns (step 0.125, exact), 9 rows: a value per column.
Field ramp() {
    Field f;
    f.grid.x = {-1.0, 1.0, 17};
    f.grid.y = {-1.0, 1.0, 9};
    for (int r = 0; r < 9; ++r)
        for (int c = 0; c < 17; ++c) f.values.push_back(f.grid.x_at(c));
    return f;
}

Picture read_picture(const std::string& path) {
    std::string error;
    const auto image = read_image(path, error);
    REQUIRE_MESSAGE(image, error);
    REQUIRE(image->channels.size() == 3);
    Picture p{image->cols, image->rows, {}};
    for (std::size_t i = 0; i < image->pixels.size(); i += 3) {
        auto byte = [&](std::size_t k) { return static_cast<std::uint8_t>(std::lround(image->pixels[i + k] * 255.0f)); };
        p.pixels.push_back({byte(0), byte(1), byte(2)});
    }
    return p;
}

Picture written(const Field& f, const OutputOptions& options) {
    ScratchDir dir;
    write_field(f, dir / "p.png", options);
    return read_picture(dir / "p.png");
}

OutputOptions fixed(double low, double high) {
    OutputOptions o;
    o.picture.scale = {ScaleChoice::Mode::Fixed, low, high};
    return o;
}

}  // namespace

TEST_CASE("--scale A:B: exact colours at chosen pixels") {
    const Field f = ramp();
    // Outside saturates at -0.5, inside at 1: x = -0.25 is halfway outside, x = 0.5 halfway inside.
    const Picture p = written(f, fixed(-0.5, 1.0));
    REQUIRE(p.cols == 17);
    REQUIRE(p.rows == 9);
    CHECK(p.at(0, 4) == kOutsideFar);               // x = -1, beyond -0.5
    CHECK(p.at(4, 4) == kOutsideFar);               // x = -0.5, the end of the scale
    CHECK(p.at(6, 4) == Rgb8{141, 169, 217});       // x = -0.25: halfway, rounded
    CHECK(p.at(8, 4) == kContourColour);            // x = 0
    CHECK(p.at(12, 4) == Rgb8{244, 180, 120});      // x = 0.5: halfway inside
    CHECK(p.at(16, 4) == kInsideFar);               // x = 1
    // The same field on the automatic scale: each side saturates at its own 99th percentile.
    CHECK(written(f, {}).at(6, 4) != Rgb8{141, 169, 217});
}

TEST_CASE("picture_colour_scale: auto per side, symmetric one for both, fixed as given") {
    std::vector<double> v;
    for (int i = 1; i <= 100; ++i) v.push_back(0.01 * i / 100);   // inside up to 0.01
    for (int i = 1; i <= 100; ++i) v.push_back(-1.0 * i / 100);   // outside up to 1
    const ColourScale a = picture_colour_scale(v, {});
    CHECK(a.inside == doctest::Approx(0.0099));
    CHECK(a.outside == doctest::Approx(0.99));
    const ColourScale s = picture_colour_scale(v, {ScaleChoice::Mode::Symmetric});
    CHECK(s.inside == s.outside);
    CHECK(s.inside == doctest::Approx(0.98));   // the 99th percentile of all 200 magnitudes
    const ColourScale x = picture_colour_scale(v, {ScaleChoice::Mode::Fixed, -0.25, 4.0});
    CHECK(x.inside == 4.0);
    CHECK(x.outside == 0.25);
    CHECK(picture_colour_scale(std::vector<double>{0.0}, {ScaleChoice::Mode::Symmetric}).inside == 1.0);
}

TEST_CASE("--levels: grey lines where the field equals a level, the zero line stays black") {
    const Field f = ramp();
    SUBCASE("N per side, up to the scale's ends") {
        OutputOptions o = fixed(-1.0, 1.0);
        o.picture.level_count = 2;
        CHECK(picture_levels(ColourScale{1.0, 1.0}, o.picture) == std::vector<double>{-1.0, -0.5, 0.5, 1.0});
        const Picture p = written(f, o);
        for (int r = 0; r < 9; ++r) {
            CHECK(p.at(4, r) == kLevelColour);    // x = -0.5
            CHECK(p.at(8, r) == kContourColour);  // x = 0
            CHECK(p.at(12, r) == kLevelColour);   // x = 0.5
            CHECK(p.at(16, r) == kLevelColour);   // x = 1
            CHECK(p.at(10, r) != kLevelColour);   // x = 0.25: no level
        }
    }
    SUBCASE("values given; zero among them is the contour's") {
        OutputOptions o = fixed(-1.0, 1.0);
        o.picture.levels = {0.25, 0.0, -0.75};
        CHECK(picture_levels(ColourScale{1.0, 1.0}, o.picture) == std::vector<double>{-0.75, 0.25});
        const Picture p = written(f, o);
        CHECK(p.at(2, 0) == kLevelColour);    // x = -0.75
        CHECK(p.at(10, 0) == kLevelColour);   // x = 0.25
        CHECK(p.at(8, 0) == kContourColour);
        CHECK(p.at(12, 0) == Rgb8{244, 180, 120});
    }
    SUBCASE("between nodes the line takes the nearer side, one pixel wide") {
        OutputOptions o = fixed(-1.0, 1.0);
        o.picture.levels = {0.3};   // between x = 0.25 (|-0.05|) and x = 0.375 (|0.075|)
        const Picture p = written(f, o);
        CHECK(p.at(10, 0) == kLevelColour);
        CHECK(p.at(11, 0) != kLevelColour);
    }
}

TEST_CASE("--legend: a colour bar with ticks right of the picture, the ranges below it") {
    const Field f = ramp();
    OutputOptions o = fixed(-0.5, 1.0);
    o.picture.levels = {0.5};
    const Picture plain = written(f, o);
    o.picture.legend = true;
    const Picture p = written(f, o);
    const ColourScale scale{1.0, 0.5};
    const LegendLayout l = legend_layout(17, 9, legend_ticks(scale), legend_caption(f.grid, 0, o.picture));
    CHECK(legend_ticks(scale) == std::vector<std::string>{"1", "0.5", "0", "-0.25", "-0.5"});
    CHECK(legend_caption(f.grid, 0, o.picture) == std::vector<std::string>{"x [-1, 1]  y [-1, 1]"});
    REQUIRE(p.cols == l.cols);
    REQUIRE(p.rows == l.rows);
    // Bounds: the picture unchanged at the top left, the bar right of it, the caption below.
    CHECK(l.bar_x >= 17);
    CHECK(l.caption_y >= 9);
    CHECK(l.bar_y + l.bar_height <= l.caption_y);
    CHECK(l.label_x + text_width("-0.25", 1) <= l.cols);
    CHECK(l.cols >= text_width("x [-1, 1]  y [-1, 1]", 1));
    for (int r = 0; r < 9; ++r)
        for (int c = 0; c < 17; ++c) CHECK(p.at(c, r) == plain.at(c, r));
    // The bar: deep orange at the top, deep blue at the bottom, black at 0, the levels grey.
    const int mid = l.bar_x + l.bar_width / 2;
    CHECK(p.at(mid, l.bar_y) == kInsideFar);
    CHECK(p.at(mid, l.bar_y + l.bar_height - 1) == kOutsideFar);
    CHECK(p.at(mid, l.bar_y + (l.bar_height - 1) / 2) == kContourColour);
    CHECK(p.at(mid, l.bar_y + 1) == value_colour(legend_bar_value(scale, 1, l.bar_height), scale));
    CHECK(l.bar_height % 2 == 1);   // so 0 has a row of its own
    CHECK(legend_bar_value(scale, (l.bar_height - 1) / 4, l.bar_height) == 0.5);
    CHECK(p.at(mid, l.bar_y + (l.bar_height - 1) / 4) == kLevelColour);
    // Text: ink in the tick labels' column and on the caption line, white elsewhere below.
    int label_ink = 0, caption_ink = 0;
    for (int r = 0; r < l.rows; ++r)
        for (int c = l.label_x; c < l.cols; ++c) label_ink += p.at(c, r) == Rgb8{0, 0, 0};
    for (int r = l.caption_y; r < l.rows; ++r)
        for (int c = 0; c < l.cols; ++c) caption_ink += p.at(c, r) == Rgb8{0, 0, 0};
    CHECK(label_ink > 5 * 10);
    CHECK(caption_ink > 100);
    CHECK(p.at(0, l.caption_y - 1) == Rgb8{255, 255, 255});
}

TEST_CASE("legend caption: a 3D slice's position, or the plane it was given") {
    Grid g;
    g.dims = 3;
    g.x = {0, 2, 5};
    g.y = {-1, 1, 5};
    g.z = {-1, 1, 9};
    PictureStyle style;
    CHECK(legend_caption(g, 6, style) == std::vector<std::string>{"x [0, 2]  y [-1, 1]", "z = 0.5 (slice 6 of 9)"});
    g.z = {0.25, 0.25, 1};
    CHECK(legend_caption(g, 0, style)[1] == "z = 0.25");
    style.axes = "yz";
    style.plane = "x = 0.3";
    CHECK(legend_caption(g, 0, style) == std::vector<std::string>{"y [0, 2]  z [-1, 1]", "x = 0.3"});
}

TEST_CASE("bitmap font: glyph rows, unknown characters as '?', widths") {
    CHECK(glyph_rows('1') == std::array<std::uint8_t, 7>{0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E});
    CHECK(glyph_rows('~') == glyph_rows('?'));
    CHECK(text_width("", 1) == 0);
    CHECK(text_width("-0.5", 2) == (4 * 6 - 1) * 2);
    int inked = 0;
    draw_text("-", 0, 0, 2, [&](int x, int y) {
        CHECK(y >= 6);   // the minus sign is row 3 of 7, doubled: rows 6 and 7
        CHECK(y <= 7);
        CHECK(x < 10);
        ++inked;
    });
    CHECK(inked == 5 * 2 * 2);
}
