// tests/unit/cli_fv_test.cpp — the fv engine on the command line: --steps writes each
// definition's pictures in order of computation, --compare prints the error report, and bad
// --palette / --steps / --compare values are usage errors with exact messages.
#include "cli_support.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

using fortu::test::quote;
using fortu::test::run_fortu;
using fortu::test::run_shell;

namespace {

const char* kSteps = "ARGUMENT X, Y;\nVARIABLE A = 0.25 - X*X - Y*Y;\nVARIABLE B = Y - X;\nVARIABLE C = A & B;\n"
                     "RETURN C | -X;\n";

std::vector<std::string> folder_names(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace

TEST_CASE("--steps writes every definition's value picture and M-images, named in order") {
    fortu::test::ScratchDir t;
    const std::string m = quote(t.write("steps.fortu", kSteps));
    const auto r = run_fortu("run " + m + " --engine fv --size 9 --steps " + quote(t / "steps"));
    CHECK(r.status == 0);
    CHECK(r.out == "wrote 20 step files (9x9) into " + (t / "steps") + ": 01_A.png ... 04_RETURN_m4.png\n");
    std::vector<std::string> expected;
    for (const char* step : {"01_A", "02_B", "03_C", "04_RETURN"}) {
        expected.push_back(std::string(step) + ".png");
        for (int k = 1; k <= 4; ++k) expected.push_back(std::string(step) + "_m" + std::to_string(k) + ".png");
    }
    CHECK(folder_names(t.path / "steps") == expected);
    // Unquantised: the value picture and one EXR of the M-images per step.
    CHECK(run_fortu("run " + m + " --engine fv --palette float --size 9 --steps " + quote(t / "float")).status == 0);
    CHECK(folder_names(t.path / "float") ==
          std::vector<std::string>{"01_A.png", "01_A_m.exr", "02_B.png", "02_B_m.exr", "03_C.png", "03_C_m.exr",
                                   "04_RETURN.png", "04_RETURN_m.exr"});
}

TEST_CASE("--compare reports the error against another engine") {
    fortu::test::ScratchDir t;
    const std::string m = quote(t.write("disc.fortu", "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n"));
    const auto r = run_shell(quote(FORTU_BINARY) + " run " + m + " --engine fv --size 5 --compare voxel 2>&1");
    CHECK(r.status == 0);
    // P = 256 loses the zeros of the circle 0.25 − x² − y² at its four nodes.
    CHECK(r.out ==
          "fv, P = 256 against voxel on 5x5 = 25 nodes:\n"
          "  max |difference| 0.0394737 at (0.5, 0.5) (fv, P = 256: -0.21052631578947384, voxel: -0.25); largest |value| 1.75\n"
          "  RMS difference 0.0207202 over 25 nodes\n"
          "  sign differs at 4 nodes: (0, 0.5), (-0.5, 0), (0.5, 0), (0, -0.5)\n"
          "  invalid in only one of them: 0 nodes\n");
    const auto exact = run_shell(quote(FORTU_BINARY) + " run " + m + " --engine fv --palette float --size 5 --compare classic 2>&1");
    CHECK(exact.out ==
          "fv, unquantised against classic on 5x5 = 25 nodes:\n"
          "  max |difference| 2.22045e-16 at (-1, 1) (fv, unquantised: -1.7500000000000002, classic: -1.75); largest |value| 1.75\n"
          "  RMS difference 1.35974e-16 over 25 nodes\n"
          "  sign differs at 0 nodes\n"
          "  invalid in only one of them: 0 nodes\n");
}

TEST_CASE("bad --palette, --steps and --compare are usage errors") {
    fortu::test::ScratchDir t;
    const std::string m = quote(t.write("disc.fortu", "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n"));
    const std::string file = quote(t.write("a_file", ""));
    CHECK(run_fortu("run " + m + " --engine fv --palette 16").out == "fortu: error: --palette: '16' is not 8, 24 or float\n");
    CHECK(run_fortu("run " + m + " --palette 24").out ==
          "fortu: error: --palette: the voxel engine stores no M-images (use --engine fv)\n");
    CHECK(run_fortu("run " + m + " --steps " + quote(t / "s")).out ==
          "fortu: error: --steps: the voxel engine does not hand out its steps (use --engine fv)\n");
    CHECK(run_fortu("run " + m + " --engine fv --steps " + file).out ==
          "fortu: error: --steps: '" + (t / "a_file") + "' is a file, not a folder\n");
    CHECK(run_fortu("run " + m + " --engine fv --compare exact").out ==
          "fortu: error: --compare: unknown engine 'exact' (use classic, voxel, voxel-f32, sign or fv)\n");
    CHECK(run_fortu("run " + m + " --engine fv --compare sign").out ==
          "fortu: error: --compare: the sign engine computes no values to compare with (use classic, voxel, "
          "voxel-f32 or fv)\n");
    CHECK(run_fortu("run " + m + " --sign-only --compare voxel").out ==
          "fortu: error: --compare: the sign engine computes no values to compare\n");
    CHECK(run_fortu("run " + m + " --engine fv --palette 16").status == 2);
}
