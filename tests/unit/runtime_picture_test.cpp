// tests/unit/runtime_picture_test.cpp — files written through OpenImageIO and read back: the
// picture's colours (inside, outside, contour, invalid), 3D slices, the float EXR, M-images.
#include "test_support.hpp"
#include "runtime/exr.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/palette.hpp"
#include "runtime/picture.hpp"

#include <OpenImageIO/imageio.h>
#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

using namespace fortu;
namespace fs = std::filesystem;

namespace {

using fortu::test::ScratchDir;


struct Image {
    OIIO::ImageSpec spec;
    std::vector<float> pixels;   // for float files
    std::vector<std::uint8_t> bytes;   // for 8-bit files
};

Image read_image(const std::string& path, bool as_float = false, int subimage = 0) {
    auto in = OIIO::ImageInput::open(path);
    REQUIRE_MESSAGE(in, OIIO::geterror());
    Image image;
    REQUIRE(in->seek_subimage(subimage, 0));
    image.spec = in->spec();
    const std::size_t n = image.spec.image_pixels() * image.spec.nchannels;
    if (as_float) {
        image.pixels.resize(n);
        REQUIRE(in->read_image(subimage, 0, 0, image.spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data()));
    } else {
        image.bytes.resize(n);
        REQUIRE(in->read_image(subimage, 0, 0, image.spec.nchannels, OIIO::TypeDesc::UINT8, image.bytes.data()));
    }
    return image;
}

Rgb8 pixel(const Image& image, int col, int row) {
    const std::size_t at = (static_cast<std::size_t>(row) * image.spec.width + col) * 3;
    return {image.bytes[at], image.bytes[at + 1], image.bytes[at + 2]};
}

Field sample2(int cols, int rows, const std::function<double(double, double)>& fn) {
    Field f;
    f.grid.x = {-1.0, 1.0, cols};
    f.grid.y = {-1.0, 1.0, rows};
    f.values.resize(f.grid.points());
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) f.values[f.grid.index(c, r)] = fn(f.grid.x_at(c), f.grid.y_at(r));
    return f;
}

Field sample3(int cols, int rows, int slices, const std::function<double(double, double, double)>& fn) {
    Field f;
    f.grid.dims = 3;
    f.grid.x = {-1.0, 1.0, cols};
    f.grid.y = {-1.0, 1.0, rows};
    f.grid.z = {-1.0, 1.0, slices};
    f.values.resize(f.grid.points());
    const Grid& g = f.grid;
    for (int s = 0; s < slices; ++s)
        for (int r = 0; r < rows; ++r)
            for (int c = 0; c < cols; ++c) f.values[g.index(c, r, s)] = fn(g.x_at(c), g.y_at(r), g.z_at(s));
    return f;
}

// A disc of radius 0.5 with one invalid point at (3, 17).
Field disc() {
    Field f = sample2(21, 21, [](double x, double y) { return 0.25 - x * x - y * y; });
    f.values[f.grid.index(3, 17)] = std::nan("");
    return f;
}

int channel(const OIIO::ImageSpec& spec, const std::string& name) {
    const int i = spec.channelindex(name);
    REQUIRE_MESSAGE(i >= 0, name);
    return i;
}

}  // namespace

TEST_CASE("value_colour: warm inside, blue outside, saturating at each side's scale, magenta invalid") {
    const ColourScale unit{1.0, 1.0};
    CHECK(value_colour(0.0, unit) == kInsideNear);
    CHECK(value_colour(1.0, unit) == kInsideFar);
    CHECK(value_colour(7.0, unit) == kInsideFar);
    CHECK(value_colour(-1e-300, unit) == kOutsideNear);
    CHECK(value_colour(-2.0, ColourScale{0.1, 2.0}) == kOutsideFar);
    CHECK(value_colour(0.5, unit) == Rgb8{244, 180, 120});   // halfway, rounded
    CHECK(value_colour(0.05, ColourScale{0.1, 2.0}) == Rgb8{244, 180, 120});
    CHECK(value_colour(std::nan(""), unit) == kInvalidColour);
    CHECK(value_colour(-std::numeric_limits<double>::infinity(), unit) == kInvalidColour);
    SUBCASE("bands darken between multiples of 1/bands, not on them") {
        CHECK(value_colour(0.5, unit, 2) == value_colour(0.5, unit));
        const Rgb8 between = value_colour(0.25, unit, 2), plain = value_colour(0.25, unit);
        CHECK(between.r < plain.r);
        CHECK(between.b < plain.b);
    }
}

TEST_CASE("colour_scale: the 99th percentile of |finite values| on each side") {
    std::vector<double> v;
    for (int i = 1; i <= 100; ++i) v.push_back(i);
    for (int i = 1; i <= 201; ++i) v.push_back(-0.5 * i);
    v.push_back(std::nan(""));
    v.push_back(-std::numeric_limits<double>::infinity());
    const ColourScale s = colour_scale(v);
    CHECK(s.inside == 99.0);    // index floor(0.99 · 99) of 1..100
    CHECK(s.outside == 99.5);   // index floor(0.99 · 200) = 198 of 0.5..100.5
    const ColourScale none = colour_scale(std::vector<double>{});
    CHECK(none.inside == 1.0);
    CHECK(none.outside == 1.0);
    const ColourScale only_outside = colour_scale(std::vector<double>{0.0, -4.0, -4.0});
    CHECK(only_outside.inside == 4.0);
    CHECK(only_outside.outside == 4.0);
}

TEST_CASE("render_slice: the contour pixel is the one nearer to zero, or exactly zero") {
    Field f;
    f.grid.x = {0.0, 1.0, 4};
    f.values = {1.0, -3.0, 0.0, 2.0};
    const auto pixels = render_slice(f, 0, ColourScale{}, OutputOptions{});
    CHECK(pixels[0] == kContourColour);
    CHECK(pixels[1] == kOutsideFar);
    CHECK(pixels[2] == kContourColour);
    CHECK(pixels[3] == kInsideFar);
    OutputOptions plain;
    plain.draw_contour = false;
    CHECK(render_slice(f, 0, ColourScale{}, plain)[0] == kInsideFar);
}

namespace {
/// render_slice's marking spelt out pixel by pixel, level by level: what the picture must show.
std::vector<Rgb8> reference_slice(const Field& field, const ColourScale& scale, const OutputOptions& options) {
    const int cols = field.grid.cols(), rows = field.grid.rows();
    const std::vector<double>& v = field.values;
    auto sign = [](double x) { return (x > 0.0) - (x < 0.0); };
    std::vector<Rgb8> pixels(v.size());
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const std::size_t i = static_cast<std::size_t>(r) * cols + c;
            pixels[i] = value_colour(v[i], scale, options.bands);
            if (!std::isfinite(v[i])) continue;
            auto on_level = [&](double level) {
                const double here = v[i] - level;
                if (here == 0.0) return true;
                const int dc[] = {-1, 1, 0, 0}, dr[] = {0, 0, -1, 1};
                for (int k = 0; k < 4; ++k) {
                    const int cc = c + dc[k], rr = r + dr[k];
                    if (cc < 0 || cc >= cols || rr < 0 || rr >= rows) continue;
                    const double w = v[static_cast<std::size_t>(rr) * cols + cc] - level;
                    if (std::isfinite(w) && sign(w) == -sign(here) && std::abs(w) >= std::abs(here)) return true;
                }
                return false;
            };
            for (double level : picture_levels(scale, options.picture))
                if (on_level(level)) pixels[i] = kLevelColour;
            if (options.draw_contour && on_level(0.0)) pixels[i] = kContourColour;
        }
    return pixels;
}
}  // namespace

TEST_CASE("render_slice: every pixel as the level-by-level rule marks it, with levels, runs, ties and invalid values") {
    // Waves with plateaus (runs of one value), exact zeros and level values, ties between
    // neighbours, NaN and ±inf, on an odd-sized grid.
    Field f = sample2(37, 23, [](double x, double y) {
        const double wave = std::sin(7 * x) * std::cos(5 * y) * 1.5;
        return std::abs(wave) < 0.3 ? std::round(wave * 4) / 4 : wave;
    });
    f.values[f.grid.index(0, 0)] = std::nan("");
    f.values[f.grid.index(5, 7)] = std::numeric_limits<double>::infinity();
    f.values[f.grid.index(6, 7)] = -std::numeric_limits<double>::infinity();
    f.values[f.grid.index(20, 11)] = 0.5;
    f.values[f.grid.index(21, 11)] = -0.5;
    const ColourScale scale = colour_scale(f.values);
    int cases = 0;
    for (const std::vector<double>& levels :
         {std::vector<double>{}, {0.5}, {-0.5, 0.25, 1.0}, {-0.0, 0.75}, {-1e300, 1e300}}) {
        for (int count : {0, 3}) {
            for (bool contour : {true, false}) {
                OutputOptions options;
                options.picture.levels = levels;
                options.picture.level_count = levels.empty() ? count : 0;
                options.draw_contour = contour;
                CAPTURE(levels.size());
                CAPTURE(count);
                CAPTURE(contour);
                CHECK(render_slice(f, 0, scale, options) == reference_slice(f, scale, options));
                ++cases;
            }
        }
    }
    CHECK(cases == 20);
}

TEST_CASE("png: a picture of at most 256 colours is written with a palette and reads back as the same RGB") {
    // Colours as a count: 256 fit a palette, 257 do not; each reads back as the same pixels.
    ScratchDir dir;
    for (const int colours : {1, 3, 256, 257}) {
        CAPTURE(colours);
        const int cols = 40, rows = 33;
        std::vector<std::uint8_t> rgb(static_cast<std::size_t>(cols) * rows * 3);
        for (std::size_t i = 0; i < rgb.size() / 3; ++i) {
            const std::size_t colour = (i * 7) % colours;   // every colour used, in runs and scattered
            rgb[3 * i] = static_cast<std::uint8_t>(colour % 256);
            rgb[3 * i + 1] = static_cast<std::uint8_t>(colour / 256 * 200);
            rgb[3 * i + 2] = static_cast<std::uint8_t>(255 - colour % 97);
        }
        const std::string path = dir / fmt::format("colours{}.png", colours);
        write_image_8bit(path, cols, rows, 3, rgb, OutputOptions{});
        const std::string file = test::read_file(path);
        REQUIRE(file.size() > 26);
        CHECK(static_cast<int>(file[25]) == (colours <= 256 ? 3 : 2));   // IHDR colour type: palette, RGB
        const Image image = read_image(path);
        CHECK(image.spec.nchannels == 3);
        CHECK(image.bytes == rgb);
    }
}

TEST_CASE("png: a picture that does not compress is written whole and reads back pixel for pixel") {
    // Noise: the compressed stream is about as long as the pixels, the case the buffer of
    // libpng's worst-case size exists for.
    ScratchDir dir;
    const int cols = 301, rows = 97;
    std::vector<std::uint8_t> noise(static_cast<std::size_t>(cols) * rows * 3);
    std::uint32_t state = 12345;
    for (std::uint8_t& b : noise) {
        state = state * 1664525u + 1013904223u;
        b = static_cast<std::uint8_t>(state >> 24);
    }
    write_image_8bit(dir / "noise.png", cols, rows, 3, noise, OutputOptions{});
    const Image image = read_image(dir / "noise.png");
    CHECK(image.spec.width == cols);
    CHECK(image.spec.height == rows);
    CHECK(image.bytes == noise);
    CHECK(fs::file_size(dir / "noise.png") > noise.size());
}

TEST_CASE("png: written, read back, expected colours at inside, outside, contour, invalid pixels") {
    const Field f = disc();
    ScratchDir dir;
    write_field(f, dir / "disc.png");
    const Image image = read_image(dir / "disc.png");
    CHECK(image.spec.width == 21);
    CHECK(image.spec.height == 21);
    CHECK(image.spec.nchannels == 3);
    CHECK(image.spec.format == OIIO::TypeDesc::UINT8);

    const Rgb8 centre = pixel(image, 10, 10);   // value 0.25, the largest inside: deep orange
    CHECK(centre == kInsideFar);
    CHECK(pixel(image, 12, 10) == value_colour(f.values[f.grid.index(12, 10)], colour_scale(f.values)));
    CHECK(centre.r > centre.g);
    CHECK(centre.g > centre.b);
    const Rgb8 corner = pixel(image, 0, 0);   // value −1.75, beyond the scale: deep blue
    CHECK(corner == kOutsideFar);
    CHECK(pixel(image, 15, 10) == kContourColour);   // x = 0.5, y = 0: on the circle
    CHECK(pixel(image, 10, 5) == kContourColour);    // x = 0, y = 0.5
    CHECK(pixel(image, 3, 17) == kInvalidColour);
    CHECK(dir.entries() == 1);
}

TEST_CASE("tiff and bmp hold the same pixels as png; jpeg is written") {
    const Field f = disc();
    ScratchDir dir;
    write_field(f, dir / "a.png");
    write_field(f, dir / "a.tif");
    write_field(f, dir / "a.BMP");
    write_field(f, dir / "a.jpg");
    const auto png = read_image(dir / "a.png").bytes;
    CHECK(read_image(dir / "a.tif").bytes == png);
    CHECK(read_image(dir / "a.BMP").bytes == png);
    const Image jpeg = read_image(dir / "a.jpg");
    CHECK(jpeg.spec.width == 21);
    CHECK(dir.entries() == 4);
}

TEST_CASE("3D pictures: the middle slice by default, a chosen one, or every slice for %d") {
    const Field f = sample3(8, 6, 5, [](double x, double y, double z) { return 0.5 - x * x - y * y - z * z; });
    ScratchDir dir;
    write_field(f, dir / "mid.png");
    OutputOptions first;
    first.slice = 0;
    write_field(f, dir / "first.png", first);
    write_field(f, dir / "s_%02d.png");
    CHECK(dir.entries() == 2 + 5);
    for (int s = 0; s < 5; ++s) CHECK(fs::exists(dir / fmt::format("s_{:02d}.png", s)));
    // The middle slice (z = 0) crosses the ball, the first (z = −1) does not.
    const Image mid = read_image(dir / "mid.png");
    CHECK(mid.spec.width == 8);
    CHECK(mid.spec.height == 6);
    const Rgb8 centre = pixel(mid, 4, 3);
    CHECK(centre.r > centre.b);
    const Rgb8 outside = pixel(read_image(dir / "first.png"), 4, 3);
    CHECK(outside.b > outside.r);

    OutputOptions bad;
    bad.slice = 5;
    CHECK_THROWS_WITH_AS(write_field(f, dir / "bad.png", bad),
                         ("cannot write '" + (dir / "bad.png") + "': slice 5 is out of range 0..4").c_str(),
                         OutputError);
}

TEST_CASE("exr: channels value, n1..n4 as floats from the FV model, NaN kept, domain attribute") {
    const Field f = disc();
    const FvModel model(f);
    ScratchDir dir;
    write_field(f, dir / "disc.exr");
    const Image image = read_image(dir / "disc.exr", true);
    CHECK(image.spec.width == 21);
    CHECK(image.spec.height == 21);
    REQUIRE(image.spec.nchannels == 5);
    CHECK(image.spec.get_string_attribute("fortu:domain") == "-1:1,-1:1");
    const int value = channel(image.spec, "value");
    std::array<int, 4> n{};
    for (int k = 1; k <= 4; ++k) n[k - 1] = channel(image.spec, fmt::format("n{}", k));
    int nan_nodes = 0;
    for (std::size_t i = 0; i < f.values.size(); ++i) {
        const float* p = &image.pixels[i * 5];
        if (std::isnan(f.values[i])) CHECK(std::isnan(p[value]));
        else CHECK(p[value] == static_cast<float>(f.values[i]));
        for (int k = 1; k <= 4; ++k) {
            if (std::isnan(model.n(k, i))) CHECK(std::isnan(p[n[k - 1]]));
            else CHECK(p[n[k - 1]] == static_cast<float>(model.n(k, i)));
        }
        nan_nodes += std::isnan(p[n[0]]);
    }
    CHECK(nan_nodes == 3);
}

TEST_CASE("exr 3D: one subimage per slice with n1..n5") {
    const Field f = sample3(4, 3, 3, [](double x, double y, double z) { return x + 2 * y + 3 * z; });
    const FvModel model(f);
    ScratchDir dir;
    write_field(f, dir / "v.exr");
    auto in = OIIO::ImageInput::open(dir / "v.exr");
    REQUIRE(in);
    int subimages = 0;
    while (in->seek_subimage(subimages, 0)) ++subimages;
    CHECK(subimages == 3);
    in.reset();
    for (int s = 0; s < 3; ++s) {
        const Image image = read_image(dir / "v.exr", true, s);
        REQUIRE(image.spec.nchannels == 6);
        CHECK(image.spec.get_float_attribute("fortu:z") == static_cast<float>(f.grid.z_at(s)));
        CHECK(image.spec.get_string_attribute("fortu:domain") == "-1:1,-1:1,-1:1");
        const int n5 = channel(image.spec, "n5"), value = channel(image.spec, "value");
        const std::size_t i = f.grid.index(2, 1, s);
        const std::size_t local = f.grid.index(2, 1);
        CHECK(image.pixels[local * 6 + n5] == static_cast<float>(model.n(5, i)));
        CHECK(image.pixels[local * 6 + value] == static_cast<float>(f.values[i]));
    }
    CHECK(exr_channel_names(f.grid) == std::vector<std::string>{"value", "n1", "n2", "n3", "n4", "n5"});
}

TEST_CASE("M-images: four grey PNGs in the P = 256 palette") {
    const Field f = disc();
    const FvModel model(f);
    ScratchDir dir;
    write_mimages(f, dir / "m_%d.png");
    CHECK(dir.entries() == 4);
    for (int k = 1; k <= 4; ++k) {
        const Image image = read_image(dir / fmt::format("m_{}.png", k));
        REQUIRE(image.spec.nchannels == 1);
        REQUIRE(image.bytes.size() == f.values.size());
        for (std::size_t i = 0; i < f.values.size(); ++i)
            CHECK(image.bytes[i] == palette_encode(model.n(k, i), Palette::Grey8));
    }
    // n3 > 0 everywhere it is valid, so M3 sits in the upper half of the codes.
    const Image m3 = read_image(dir / "m_3.png");
    CHECK(m3.bytes[f.grid.index(10, 10)] >= 128);
}

TEST_CASE("M-images: 24-bit RGB palette decodes to n within 1/(2^24 − 1)") {
    const Field f = disc();
    const FvModel model(f);
    ScratchDir dir;
    OutputOptions options;
    options.mimage_palette = Palette::Rgb24;
    write_mimages(f, dir / "rgb%d.png", options);
    const Image image = read_image(dir / "rgb2.png");
    REQUIRE(image.spec.nchannels == 3);
    const std::size_t i = f.grid.index(12, 4);
    const std::uint32_t m = rgb24_unpack(image.bytes[3 * i], image.bytes[3 * i + 1], image.bytes[3 * i + 2]);
    CHECK(m == palette_encode(model.n(2, i), Palette::Rgb24));
    CHECK(std::abs(palette_decode(m, Palette::Rgb24) - model.n(2, i)) <= 1.0 / 16777215);
}

TEST_CASE("M-images: .exr is the float EXR; other paths are refused with a reason") {
    const Field f = disc();
    ScratchDir dir;
    write_mimages(f, dir / "m.exr");
    CHECK(read_image(dir / "m.exr", true).spec.nchannels == 5);
    CHECK_FALSE(mimages_path_problem("m.exr"));
    CHECK_FALSE(mimages_path_problem("m_%d.png"));
    CHECK(mimages_path_problem("m.png") ==
          "M-images are n+2 pictures: put %d in the name (e.g. 'm_%d.png') or use .exr");
    CHECK(mimages_path_problem("m_%d.jpg") == "JPEG is lossy and would corrupt the M-image codes; use .png");
    CHECK(mimages_path_problem("m_%d.csv") ==
          "M-images need a .exr, .vti, .pvti or .hdf file or a picture series such as 'm_%d.png'");
    CHECK_FALSE(mimages_path_problem("m.pvti"));
    CHECK_FALSE(mimages_path_problem("m.hdf"));
    CHECK(mimages_path_problem("m.vdb") == "OpenVDB holds the value alone (narrow band, --band); M-images need a .exr, "
                                           ".vti, .pvti or .hdf file or a picture series such as 'm_%d.png'");
    CHECK(mimages_path_problem("m.nrrd") ==
          "NRRD holds the value alone; M-images need a .exr, .vti, .pvti or .hdf file or a picture series such as "
          "'m_%d.png'");
    CHECK_THROWS_WITH_AS(write_mimages(f, dir / "m.png"),
                         ("cannot write '" + (dir / "m.png") +
                          "': M-images are n+2 pictures: put %d in the name (e.g. 'm_%d.png') or use .exr")
                             .c_str(),
                         OutputError);
    CHECK(dir.entries() == 1);
}

TEST_CASE("an OpenImageIO failure is an OutputError naming the file, and leaves no temporary") {
    ScratchDir dir;
    const std::vector<std::uint8_t> pixels(4 * 3, 0);
    try {
        write_image_8bit(dir / "x.nosuchformat", 2, 2, 3, pixels, OutputOptions{});
        FAIL("expected an OutputError");
    } catch (const OutputError& e) {
        CHECK(e.path() == dir / "x.nosuchformat");
        CHECK(std::string(e.what()).starts_with("cannot write '" + (dir / "x.nosuchformat") + "': "));
        CHECK_FALSE(e.reason().empty());
    }
    CHECK(dir.entries() == 0);
}

TEST_CASE("a written file gets the usual permissions of a new file") {
    ScratchDir dir;
    { std::ofstream(dir / "reference"); }
    write_field(disc(), dir / "disc.png");
    CHECK(fs::status(dir / "disc.png").permissions() == fs::status(dir / "reference").permissions());
}
