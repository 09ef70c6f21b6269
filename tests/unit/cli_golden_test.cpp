// tests/unit/cli_golden_test.cpp — the tests of the tester: `fortu golden` over small suites
// made in temporary folders (issue 7's acceptance), with its exact report lines.
#include "cli/golden/golden_spec.hpp"
#include "cli_support.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

using fortu::test::run_fortu;

namespace {

namespace fs = std::filesystem;

/// A scratch folder holding a suite.
struct TempDir : fortu::test::ScratchDir {
    bool has(const std::string& name) const { return fs::exists(path / name); }
    /// `fortu golden ARGS` in this folder: status and stdout + stderr.
    fortu::test::CommandResult golden(const std::string& args) const {
        return run_fortu("golden " + args, path.string(), /*with_stdout=*/true);
    }
};

// A disc of radius 0.5, checked by value, by side and by its picture.
const char* kDisc =
    "// golden-size 16x16\n"
    "// golden-output png\n"
    "// expect-value 0 0: 0.25\n"
    "// expect-inside 0.1 0.1\n"
    "// expect-outside 0.9 0.9\n"
    "ARGUMENT X(-1, 1), Y(-1, 1);\n"
    "RETURN 0.25 - X*X - Y*Y;\n";

const char* kTypo =
    "// expect-error 3:12: unknown name 'Y2'\n"
    "ARGUMENT X(-1, 1), Y(-1, 1);\n"
    "RETURN X + Y2;\n";

/// A suite with references made by --update: disc.fortu + disc.expected.png, typo.fortu.
void make_suite(const TempDir& t) {
    t.write("disc.fortu", kDisc);
    t.write("typo.fortu", kTypo);
    REQUIRE(t.golden(". --update").status == 0);
    REQUIRE(t.has("disc.expected.png"));
}

}  // namespace

TEST_CASE("a passing suite passes, with one line per test and the summary") {
    TempDir t;
    make_suite(t);
    const auto r = t.golden(".");
    CHECK(r.status == 0);
    CHECK(r.out == "PASS disc.fortu\nPASS typo.fortu\n2 tests: 2 passed, 0 failed\n");
    SUBCASE("--jobs keeps the order and the lines whole") {
        CHECK(t.golden(". --jobs 4").out == r.out);
    }
    SUBCASE("one engine") {
        CHECK(t.golden("disc.fortu --engine classic").out == "PASS disc.fortu\n1 test: 1 passed, 0 failed\n");
    }
}

TEST_CASE("the first --update makes the missing references and reports them") {
    TempDir t;
    t.write("disc.fortu", kDisc);
    const auto before = t.golden("disc.fortu");
    CHECK(before.status == 1);
    CHECK(before.out ==
          "FAIL disc.fortu: disc.expected.png is missing (run with --update to create it)\n"
          "1 test: 0 passed, 1 failed\n");
    CHECK_FALSE(t.has("disc.expected.png"));
    const auto update = t.golden("disc.fortu --update");
    CHECK(update.status == 0);
    CHECK(update.out == "UPDATE disc.fortu: rewrote disc.expected.png\n1 test: 1 passed, 0 failed\n");
    CHECK(t.golden("disc.fortu").status == 0);
}

TEST_CASE("changing one constant fails with the worst pixel and a diff image; --update then passes") {
    TempDir t;
    make_suite(t);
    const std::string reference = t.read("disc.expected.png");
    t.write("disc.fortu", std::string(kDisc).replace(std::string(kDisc).find("0.25 - X"), 4, "0.36"));
    const auto r = t.golden("disc.fortu");
    CHECK(r.status == 1);
    CHECK(r.out ==
          "FAIL disc.fortu: line 3: expect-value 0 0 (both engines): expected 0.25 +- 1e-09, got 0.36\n"
          // The colour scale follows the values, so most pixels change; the worst is a pixel that
          // the wider disc's zero contour (black) now crosses.
          "  disc.expected.png (both engines): 248 of 256 pixels differ by more than 0 level(s) (max error 252 "
          "levels); worst at pixel "
          "(5, 4) (x -0.33333333333333337, y 0.4666666666666667): expected (226, 235, 252), got (0, 0, 0)\n"
          "    new output: disc.actual.png\n"
          "    diff image: disc.diff.png\n"
          "1 test: 0 passed, 1 failed\n");
    CHECK(t.has("disc.diff.png"));
    CHECK(t.has("disc.actual.png"));
    CHECK(t.read("disc.expected.png") == reference);  // a failing run never touches references

    const auto update = t.golden("disc.fortu --update");
    CHECK(update.status == 0);
    CHECK(update.out == "UPDATE disc.fortu: rewrote the script's line 3, disc.expected.png\n"
                        "1 test: 1 passed, 0 failed\n");
    CHECK(t.read("disc.fortu").find("// expect-value 0 0: 0.36\n") != std::string::npos);
    CHECK_FALSE(t.has("disc.diff.png"));
    CHECK_FALSE(t.has("disc.actual.png"));
    CHECK(t.golden("disc.fortu").out == "PASS disc.fortu\n1 test: 1 passed, 0 failed\n");
}

TEST_CASE("a wrong expected diagnostic fails with both texts; --update then passes") {
    TempDir t;
    t.write("typo.fortu", "// expect-error 3:8: unknown name 'Y3'\nARGUMENT X(-1, 1), Y(-1, 1);\nRETURN X + Y2;\n");
    const auto r = t.golden("typo.fortu");
    CHECK(r.status == 1);
    CHECK(r.out == "FAIL typo.fortu: the errors differ\n"
                   "    expected:\n"
                   "      3:8: unknown name 'Y3'\n"
                   "    actual:\n"
                   "      3:12: unknown name 'Y2'\n"
                   "1 test: 0 passed, 1 failed\n");
    CHECK(t.golden("typo.fortu --update").out ==
          "UPDATE typo.fortu: rewrote the script's expect-error lines\n1 test: 1 passed, 0 failed\n");
    CHECK(t.read("typo.fortu") == kTypo);
    CHECK(t.golden("typo.fortu").status == 0);
}

TEST_CASE("a script that should fail but compiles, or should compile but fails") {
    TempDir t;
    t.write("ok.fortu", "// expect-error 2:1: unknown name 'Q'\nARGUMENT X, Y;\nRETURN X;\n");
    t.write("broken.fortu", "// expect-inside 0 0\nARGUMENT X, Y;\nRETURN X + Q;\n");
    CHECK(t.golden(". ").out == "FAIL broken.fortu: the script does not compile:\n"
                                "    3:12: unknown name 'Q'\n"
                                "FAIL ok.fortu: the errors differ\n"
                                "    expected:\n"
                                "      2:1: unknown name 'Q'\n"
                                "    actual:\n"
                                "      (none: the script compiles)\n"
                                "2 tests: 0 passed, 2 failed\n");
}

TEST_CASE("a corrupted or wrong-sized reference image fails with a clear message") {
    TempDir t;
    make_suite(t);
    SUBCASE("not a PNG") {
        t.write("disc.expected.png", "this is not an image");
        const auto r = t.golden("disc.fortu");
        CHECK(r.status == 1);
        CHECK(r.out == "FAIL disc.fortu: disc.expected.png (both engines): cannot be compared: "
                       "'disc.expected.png' is not a PNG file\n"
                       "    new output: disc.actual.png\n"
                       "1 test: 0 passed, 1 failed\n");
    }
    SUBCASE("cut short") {
        const std::string png = t.read("disc.expected.png");
        REQUIRE(png.size() > 200);
        t.write("disc.expected.png", png.substr(0, 200));   // in its IDAT, after the palette
        const auto r = t.golden("disc.fortu");
        CHECK(r.status == 1);
        CHECK(r.out == "FAIL disc.fortu: disc.expected.png (both engines): cannot be compared: "
                       "'disc.expected.png' is cut short: its IDAT chunk at byte 151 needs 144 bytes, the file ends "
                       "at 200\n"
                       "    new output: disc.actual.png\n"
                       "1 test: 0 passed, 1 failed\n");
    }
    SUBCASE("a flipped byte") {
        std::string png = t.read("disc.expected.png");
        png[200] = static_cast<char>(png[200] ^ 0xff);
        t.write("disc.expected.png", png);
        CHECK(t.golden("disc.fortu").out ==
              "FAIL disc.fortu: disc.expected.png (both engines): cannot be compared: 'disc.expected.png' is "
              "damaged: its IDAT chunk at byte 151 fails its CRC\n"
              "    new output: disc.actual.png\n"
              "1 test: 0 passed, 1 failed\n");
    }
    SUBCASE("another size") {
        t.write("disc.fortu", std::string(kDisc).replace(std::string(kDisc).find("16x16"), 5, "8x8"));
        CHECK(t.golden("disc.fortu").out ==
              "FAIL disc.fortu: disc.expected.png (both engines): cannot be compared: the reference is 16x16 "
              "with 3 channels, the new image 8x8 with 3 channels\n"
              "    new output: disc.actual.png\n"
              "1 test: 0 passed, 1 failed\n");
    }
    // --update repairs it.
    CHECK(t.golden("disc.fortu --update").status == 0);
    CHECK(t.golden("disc.fortu").status == 0);
}

TEST_CASE("--update never touches passing references") {
    TempDir t;
    make_suite(t);
    const auto stamp = fs::last_write_time(t.path / "disc.expected.png");
    const auto r = t.golden(". --update");
    CHECK(r.out == "PASS disc.fortu\nPASS typo.fortu\n2 tests: 2 passed, 0 failed\n");
    CHECK(fs::last_write_time(t.path / "disc.expected.png") == stamp);
    CHECK(t.read("disc.fortu") == kDisc);
}

TEST_CASE("values: npy, csv and svg references compared with the stated tolerance") {
    TempDir t;
    const std::string script =
        "// golden-size 5x3\n// golden-tolerance 0.01\n// golden-output npy csv svg\n"
        "ARGUMENT X(-1, 1), Y(-1, 1);\nRETURN 0.25 - X*X - Y*Y;\n";
    t.write("v.fortu", script);
    REQUIRE(t.golden("v.fortu --update").status == 0);
    t.write("v.fortu", std::string(script).replace(script.find("0.25"), 4, "0.255"));
    CHECK(t.golden("v.fortu").out == "PASS v.fortu\n1 test: 1 passed, 0 failed\n");
    t.write("v.fortu", std::string(script).replace(script.find("0.25"), 4, "0.27"));
    CHECK(t.golden("v.fortu").out ==
          "FAIL v.fortu: v.expected.npy (both engines): 15 of 15 values differ by more than 0.01; worst at node "
          "(col 0, row 0) = (-1, 1): expected -1.75, got -1.73\n"
          "    new output: v.actual.npy\n"
          "    diff image: v.values-diff.png\n"
          "  v.expected.csv (both engines): 15 of 45 numbers differ by more than 0.01; worst on line 2: expected "
          "-1.75, got -1.73\n"
          "    expected: -1,1,-1.75\n"
          "    actual:   -1,1,-1.73\n"
          "    new output: v.actual.csv\n"
          // The contour ran through grid nodes (value exactly 0) and now cuts the edges beside them.
          // (in pixels of the 5x3 picture: 0.027 px is 0.0133 in X)
          "  v.expected.svg (both engines): 9 of 38 numbers differ by more than 0.01; worst on line 6: expected "
          "3.5, got 3.527\n"
          "    expected: <polyline points=\"1.500,1.500 1.500,1.500 1.500,1.500 2.500,1.750 3.500,1.500 3.500,1.500 "
          "3.500,1.500 2.500,1.250 1.5...\n"
          "    actual:   <polyline points=\"1.500,1.480 1.473,1.500 1.500,1.520 2.500,1.770 3.500,1.520 3.527,1.500 "
          "3.500,1.480 2.500,1.230 1.5...\n"
          "    new output: v.actual.svg\n"
          "1 test: 0 passed, 1 failed\n");
    CHECK(t.has("v.values-diff.png"));
}

TEST_CASE("malformed directives, missing expectations and wrong singular points fail, never pass silently") {
    TempDir t;
    t.write("typo.fortu", "// expect-valeu 0 0: 1\n// golden-size 0x4\nARGUMENT X, Y;\nRETURN X;\n");
    t.write("none.fortu", "ARGUMENT X, Y;\nRETURN X;\n");
    t.write("singular.fortu", "// expect-singular (0, 0)\nARGUMENT X, Y;\nRETURN X*X + Y*Y;\n");
    t.write("args.fortu", "// expect-inside 0 0 0\nARGUMENT X, Y;\nRETURN 1;\n");
    t.write("value.fortu", "// expect-value 0 0 0.5\nARGUMENT X, Y;\nRETURN 1;\n");
    const auto r = t.golden(".");
    CHECK(r.status == 1);
    CHECK(r.out ==
          "FAIL args.fortu: line 1: expect-inside gives 3 coordinate(s); the model has 2 argument(s)\n"
          "FAIL none.fortu: no expectations: add `// expect-...` lines, or NAME.expected.{png,exr,npy,csv,svg,stl,obj,ply,vti,nrrd} "
          "files or `// golden-output` for --update to create\n"
          "FAIL singular.fortu: line 1: the singular points differ (matched within 1e-06)\n"
          "    expected, not found: (0, 0)\n"
          "    found: none\n"
          "FAIL typo.fortu: line 1: unknown directive 'expect-valeu'\n"
          "  line 2: golden-size: '0x4' is not N, WxH or WxHxD (positive node counts)\n"
          "FAIL value.fortu: line 1: expect-value wants `X Y[ Z]: VALUE [+- TOLERANCE]`\n"
          "5 tests: 0 passed, 5 failed\n");
}

TEST_CASE("golden-size with more than three components is refused before its product can overflow") {
    // Found by fuzz_golden_directive: 21 components multiplied to past 2^63.
    fortu::GoldenTest test;
    CHECK(fortu::apply_directive(test, "golden-size 7x8x8x8x8x88x8x8x8x8x8x8x8x8x8x8x8x8x8x88x8", 2) ==
          "golden-size: '7x8x8x8x8x88x8x8x8x8x8x8x8x8x8x8x8x8x8x88x8' is not N, WxH or WxHxD (at most 3 node counts)");
    CHECK(fortu::apply_directive(test, "golden-size 65536x65536x65536", 2) ==
          "golden-size: '65536x65536x65536' is too large for a golden test (at most 4194304 points)");
    CHECK(fortu::apply_directive(test, "golden-size 4x5x6", 2) == "");
}

TEST_CASE("a manifest runs scripts kept elsewhere, with references beside it") {
    TempDir t;
    fs::create_directories(t.path / "models");
    fs::create_directories(t.path / "suite");
    t.write("models/a.fortu", "ARGUMENT X(-1, 1), Y(-1, 1);\nRETURN X - Y;\n");
    t.write("models/b.fortu", "// expect-inside 0.5 0\nARGUMENT X(-1, 1), Y(-1, 1);\nRETURN X - 2*Y;\n");
    t.write("suite/all.golden", "# every model\nscripts ../models/*.fortu\ngolden-size 4\ngolden-output npy\n"
                                "b: golden-engine voxel\n");
    CHECK(t.golden("suite --update").out == "UPDATE suite/all.golden:a: rewrote a.expected.npy\n"
                                            "UPDATE suite/all.golden:b: rewrote b.expected.npy\n"
                                            "2 tests: 2 passed, 0 failed\n");
    CHECK(t.has("suite/a.expected.npy"));
    CHECK(t.golden("suite").out == "PASS suite/all.golden:a\nPASS suite/all.golden:b\n2 tests: 2 passed, 0 failed\n");
    // A new script is a new test, failing until its references exist.
    t.write("models/c.fortu", "ARGUMENT X, Y;\nRETURN X;\n");
    CHECK(t.golden("suite/all.golden").out ==
          "PASS suite/all.golden:a\nPASS suite/all.golden:b\n"
          "FAIL suite/all.golden:c: suite/c.expected.npy is missing (run with --update to create it)\n"
          "3 tests: 2 passed, 1 failed\n");
    t.write("suite/bad.golden", "scripts ${FORTU_NO_SUCH_VARIABLE}/*.fortu\n");
    CHECK(t.golden("suite/bad.golden").out ==
          "FAIL suite/bad.golden: scripts ${FORTU_NO_SUCH_VARIABLE}/*.fortu: the environment variable "
          "FORTU_NO_SUCH_VARIABLE is not set\n"
          "1 test: 0 passed, 1 failed\n");
}

TEST_CASE("the classic engine's budget is a failure that says what to do") {
    TempDir t;
    // 2^30 operations per point on the classic engine: each line doubles the expanded tree.
    std::string script = "// expect-inside 0 0\nARGUMENT X, Y;\nVARIABLE A = X + Y + 1;\n";
    for (int i = 0; i < 30; ++i) script += "A = A & A;\n";
    script += "RETURN A;\n";
    t.write("deep.fortu", script);
    const auto r = t.golden("deep.fortu");
    CHECK(r.status == 1);
    CHECK(r.out.find("FAIL deep.fortu: the classic engine would need ") == 0);
    CHECK(r.out.find("declare `// golden-engine voxel` or a smaller golden-size\n") != std::string::npos);
    CHECK(t.golden("deep.fortu --engine voxel").out == "PASS deep.fortu\n1 test: 1 passed, 0 failed\n");
}

TEST_CASE("usage errors exit 2") {
    TempDir t;
    CHECK(t.golden("").status == 2);
    CHECK(t.golden("").out == "fortu: error: 'fortu golden': no tests given\n"
                              "usage: fortu golden DIR|FILE... [--engine both|classic|voxel] [--update] [--jobs N]\n");
    CHECK(t.golden("nowhere").out == "fortu: error: 'fortu golden': 'nowhere': no such file or folder\n");
    CHECK(t.golden(". --engine fast").out ==
          "fortu: error: 'fortu golden': --engine 'fast' is not both, classic or voxel\n");
    CHECK(t.golden(". --jobs 0").out ==
          "fortu: error: 'fortu golden': --jobs '0' is not a number of threads from 1 to 256\n");
    CHECK(t.golden(". --jobs").status == 2);
    CHECK(t.golden(". --frobnicate").status == 2);
    CHECK(t.golden(".").out == "fortu: error: 'fortu golden': no .fortu scripts or .golden manifests in '.'\n");
    t.write("notes.txt", "x");
    CHECK(t.golden("notes.txt").out ==
          "fortu: error: 'fortu golden': 'notes.txt' is neither a .fortu script nor a .golden manifest\n");
}

TEST_CASE("a 3D EXR reference: the worst pixel names its slice and every channel") {
    TempDir t;
    const std::string script = "// golden-size 4x4x3\n// golden-output exr\n"
                               "ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nRETURN 1 - X*X - Y*Y - Z*Z;\n";
    t.write("ball.fortu", script);
    REQUIRE(t.golden("ball.fortu --update").status == 0);
    t.write("ball.fortu", std::string(script).replace(script.find("1 - X"), 1, "1.5"));
    CHECK(t.golden("ball.fortu").out ==
          "FAIL ball.fortu: ball.expected.exr (both engines): 48 of 48 pixels differ by more than 1e-09 (max error "
          "0.50000006); worst at pixel (1, 0) of slice 0 (x -0.33333333333333337, y 1): expected (n1=-0, "
          "n2=0.5807207, n3=-0.43554053, n4=0.43554053, n5=-0.5323273, value=-1.1111112), got (n1=-0, "
          "n2=0.51343507, n3=-0.38507628, n4=0.38507628, n5=-0.66318697, value=-0.6111111)\n"
          "    new output: ball.actual.exr\n"
          "    diff image: ball.diff.exr\n"
          "1 test: 0 passed, 1 failed\n");
    CHECK(t.has("ball.diff.exr"));
}

TEST_CASE("expect-singular lists the points `fortu singular` finds; --update rewrites the list") {
    TempDir t;
    // Two discs crossing on X = 0 at Y = +-sqrt(0.5 - 0.09): their union has two corners there.
    const std::string body = "ARGUMENT X(-1, 1), Y(-1, 1);\nVARIABLE A = 0.5 - (X-0.3)^2 - Y^2;\n"
                             "VARIABLE B = 0.5 - (X+0.3)^2 - Y^2;\nRETURN A | B;\n";
    t.write("corner.fortu", "// expect-singular (0, 0.6403124237)\n// expect-singular (0, -0.6403124237)\n" + body);
    CHECK(t.golden("corner.fortu").out == "PASS corner.fortu\n1 test: 1 passed, 0 failed\n");
    t.write("corner.fortu", "// expect-singular (0, 0.64)\n// expect-singular none\n" + body);
    CHECK(t.golden("corner.fortu").out ==
          "FAIL corner.fortu: line 1: the singular points differ (matched within 1e-06)\n"
          "    expected, not found: (0, 0.64)\n"
          "    found, not expected: (0, -0.640312423743) (0, 0.640312423743)\n"
          "    found: (0, -0.640312423743) (0, 0.640312423743)\n"
          "1 test: 0 passed, 1 failed\n");
    CHECK(t.golden("corner.fortu --update").out ==
          "UPDATE corner.fortu: rewrote the script's expect-singular lines\n1 test: 1 passed, 0 failed\n");
    CHECK(t.read("corner.fortu") == "// expect-singular (0, -0.640312423743) (0, 0.640312423743)\n" + body);
    CHECK(t.golden("corner.fortu").status == 0);
}
