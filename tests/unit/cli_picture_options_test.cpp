// tests/unit/cli_picture_options_test.cpp — `--scale`, `--levels`, `--legend` on the command
// line: their parsing, their usage errors (exit 2, before evaluating), the pictures they make,
// and the PNG written without OpenImageIO's module.
#include "cli_support.hpp"
#include "test_support.hpp"

#include "cli/picture_options.hpp"
#include "runtime/image_io.hpp"
#include "runtime/picture.hpp"

#include <doctest/doctest.h>

using fortu::test::quote;
using fortu::test::run_fortu;
using namespace fortu;

namespace {

const char* kDisc = "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n";
const char* kBall = "ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nRETURN 0.25 - X*X - Y*Y - Z*Z;\n";

std::optional<ImageData> read_back(const std::string& path) {
    std::string error;
    auto image = read_image(path, error);
    REQUIRE_MESSAGE(image, error);
    return image;
}

}  // namespace

TEST_CASE("--scale and --levels: values parsed, mistakes named") {
    CHECK(parse_scale_choice("auto").mode == ScaleChoice::Mode::Auto);
    CHECK(parse_scale_choice("symmetric").mode == ScaleChoice::Mode::Symmetric);
    const ScaleChoice fixed = parse_scale_choice("-0.5:0.01");
    CHECK(fixed.mode == ScaleChoice::Mode::Fixed);
    CHECK(fixed.low == -0.5);
    CHECK(fixed.high == 0.01);
    CHECK_THROWS_WITH_AS(parse_scale_choice("wide"),
                         "--scale: 'wide' is not auto, symmetric or A:B (numbers, e.g. -0.5:0.1)", UsageError);
    CHECK_THROWS_WITH_AS(parse_scale_choice("0.1:1"),
                         "--scale: in '0.1:1' A must be below 0 and B above 0 (the colours part at 0)", UsageError);
    CHECK_THROWS_AS(parse_scale_choice("-1:nan"), UsageError);
    PictureStyle style;
    parse_levels("4", style);
    CHECK(style.level_count == 4);
    CHECK(style.levels.empty());
    parse_levels("-0.1,0.05,2.0", style);
    CHECK(style.level_count == 0);
    CHECK(style.levels == std::vector<double>{-0.1, 0.05, 2.0});
    parse_levels("2.0", style);
    CHECK(style.levels == std::vector<double>{2.0});
    CHECK_THROWS_WITH_AS(parse_levels("0", style), "--levels: '0' levels per side is not from 1 to 100", UsageError);
    std::string many = "0.5";
    for (int i = 0; i < 100; ++i) many += ",0.5";
    CHECK_THROWS_WITH_AS(parse_levels(many, style), "--levels: 101 values; at most 100", UsageError);
    CHECK_THROWS_WITH_AS(parse_levels("0.1,,0.2", style),
                         "--levels: '' is not a number in '0.1,,0.2' (use N, or values such as -0.1,0.05,0.2)",
                         UsageError);
}

TEST_CASE("fortu run: picture options in --help, errors exit 2, a 3D shaded view refuses them") {
    fortu::test::ScratchDir t;
    const std::string disc = quote(t.write("disc.fortu", kDisc)), ball = quote(t.write("ball.fortu", kBall));
    const std::string help = run_fortu("run --help", ".", true).out;
    CHECK(help.find("--legend") != std::string::npos);
    CHECK(help.find("--levels N|V1,V2,...") != std::string::npos);
    CHECK(help.find("--scale auto|symmetric|A:B") != std::string::npos);
    const auto bad = run_fortu("run " + disc + " --scale 2:1 -o " + quote(t / "x.png"));
    CHECK(bad.status == 2);
    CHECK(bad.out == "fortu: error: --scale: in '2:1' A must be below 0 and B above 0 (the colours part at 0)\n");
    const auto shaded = run_fortu("run " + ball + " --legend -o " + quote(t / "b.png"));
    CHECK(shaded.status == 2);
    CHECK(shaded.out == "fortu: error: --legend, --levels and --scale colour a plane by its values; a 3D picture "
                        "without --slice is a shaded view of the solid (add --slice z=V)\n");
    CHECK(t.entries() == 2);
}

TEST_CASE("fortu run --legend: the picture grows by the legend; a slice's caption; the module stays unloaded") {
    fortu::test::ScratchDir t;
    const std::string disc = quote(t.write("disc.fortu", kDisc)), ball = quote(t.write("ball.fortu", kBall));
    REQUIRE(run_fortu("run " + disc + " --size 64 -o " + quote(t / "plain.png")).status == 0);
    REQUIRE(run_fortu("run " + disc + " --size 64 --legend --levels 2 --scale symmetric -o " + quote(t / "l.png")).status == 0);
    const auto plain = read_back(t / "plain.png"), legend = read_back(t / "l.png");
    CHECK(plain->cols == 64);
    CHECK(plain->rows == 64);
    CHECK(legend->cols > 64);
    CHECK(legend->rows > 64);
    REQUIRE(run_fortu("run " + ball + " --size 40 --slice x=0.25 --legend -o " + quote(t / "x.png")).status == 0);
    const auto plane = read_back(t / "x.png");
    CHECK(plane->cols > 40);
    // A PNG is written by libpng in the core: OpenImageIO's module (~260 libraries) stays out.
    const auto traced = fortu::test::run_shell("LD_DEBUG=files " + quote(FORTU_BINARY) + " run " + disc +
                                               " --size 32 -o " + quote(t / "fast.png") + " 2>&1 >/dev/null");
    CHECK(traced.status == 0);
    CHECK(traced.out.find("libfortu_image.so") == std::string::npos);
    CHECK(traced.out.find("libOpenImageIO") == std::string::npos);
}
