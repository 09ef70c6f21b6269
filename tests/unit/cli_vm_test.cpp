// tests/unit/cli_vm_test.cpp — the command line with .vm models, --sign-only and
// --precision: they run, agree with the default mode, and misuse is a usage error.
#include "test_support.hpp"
#include "cli_support.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace fortu::test;

namespace {

std::string vm(const char* name) { return quote(std::string(FORTU_SHARED_DIR) + "/data/" + name); }


}  // namespace

TEST_CASE("check, eval and run accept .vm models") {
    CommandResult check = run_fortu("check " + vm("bear.vm"), ".", true);
    CHECK(check.status == 0);
    CHECK(check.out == std::string(FORTU_SHARED_DIR) + "/data/bear.vm: ok (3 arguments, 657 nodes)\n");
    CommandResult eval = run_fortu("eval " + vm("quarter.vm") + " -0.5 -0.25", ".", true);
    CHECK(eval.status == 0);
    CHECK(eval.out.rfind("value: 0.1875\n", 0) == 0);
}

TEST_CASE("a malformed .vm model is a located model error") {
    fortu::test::ScratchDir dir;
    dir.write("bad.vm", "x var-x\ny frob x\n");
    CommandResult r = run_fortu("run bad.vm", dir.path.string());
    CHECK(r.status == 1);
    CHECK(r.out == "bad.vm:2:3: error: unknown operation 'frob'\ny frob x\n  ^~~~\n"
                   "note: known: var-x var-y var-z const add sub mul div max min neg square sqrt abs exp ln sin cos\n");
}

TEST_CASE("--sign-only writes the same sign as the full evaluation") {
    fortu::test::ScratchDir dir;
    REQUIRE(run_fortu("run " + vm("prospero.vm") + " --size 96 --sign-only -o sign.csv", dir.path.string()).status == 0);
    REQUIRE(run_fortu("run " + vm("prospero.vm") + " --size 96 -o full.csv", dir.path.string()).status == 0);
    std::istringstream sign(dir.read("sign.csv")), full(dir.read("full.csv"));
    std::string a, b;
    std::getline(sign, a);
    std::getline(full, b);
    int rows = 0, inside = 0;
    while (std::getline(sign, a) && std::getline(full, b)) {
        const double s = std::stod(a.substr(a.rfind(',') + 1));
        const double f = std::stod(b.substr(b.rfind(',') + 1));
        CHECK(s == (f > 0 ? 1.0 : f < 0 ? -1.0 : 0.0));
        inside += s > 0;
        ++rows;
    }
    CHECK(rows == 96 * 96);
    CHECK(inside > 0);
}

TEST_CASE("--precision and --sign-only usage errors") {
    CommandResult bad = run_fortu("run " + vm("hi.vm") + " --precision f16");
    CHECK(bad.status == 2);
    CHECK(bad.out == "fortu: error: --precision: 'f16' is not float64 or float32\n");
    CommandResult classic = run_fortu("run " + vm("hi.vm") + " --sign-only --engine classic");
    CHECK(classic.status == 2);
    CHECK(classic.out == "fortu: error: --sign-only runs the interval renderer; it does not combine with --engine classic\n");
    CommandResult mimages = run_fortu("run " + vm("hi.vm") + " --sign-only --mimages m.exr");
    CHECK(mimages.status == 2);
    CHECK(mimages.out == "fortu: error: --sign-only computes no values; the M-images need them (drop one of the two)\n");
    CHECK(run_fortu("run " + vm("hi.vm") + " --precision float32 --size 32").status == 0);
    // --sign-only is --engine sign; naming the default engine beside it stays accepted.
    CHECK(run_fortu("run " + vm("hi.vm") + " --sign-only --engine voxel --size 8").status == 0);
    CHECK(run_fortu("run " + vm("hi.vm") + " --sign-only --engine voxel-f32").out ==
          "fortu: error: --sign-only runs the interval renderer; it does not combine with --engine voxel-f32\n");
    CHECK(run_fortu("run " + vm("hi.vm") + " --engine sign --mimages m.exr").out ==
          "fortu: error: --engine sign computes no values; the M-images need them (drop one of the two)\n");
    CommandResult point = run_fortu("eval " + vm("hi.vm") + " 0 0 --engine sign");
    CHECK(point.status == 2);
    CHECK(point.out == "fortu: error: 'fortu eval': the sign engine evaluates whole grids only (use classic, voxel or voxel-f32)\n");
}

TEST_CASE("--isa picks the compiled tapes' and transcendentals' instruction set, for run and bench") {
    CommandResult bad = run_fortu("run " + vm("hi.vm") + " --isa avx3");
    CHECK(bad.status == 2);
    CHECK(bad.out == "fortu: error: --isa: 'avx3' is not avx2 or avx512\n");
    CHECK(run_fortu("bench " + vm("hi.vm") + " --isa sse --sizes 8").out == "fortu: error: --isa: 'sse' is not avx2 or avx512\n");
    CommandResult narrow = run_fortu("run " + vm("hi.vm") + " --precision float32 --size 16 --isa avx2 --stats", ".", true);
    REQUIRE_MESSAGE(narrow.status == 0, narrow.out);
    if (narrow.out.find("compiled tapes none") == std::string::npos)   // a CPU with AVX2
        CHECK(narrow.out.find("compiled tapes AVX2, float32 transcendentals AVX2") != std::string::npos);
    CommandResult wide = run_fortu("run " + vm("hi.vm") + " --precision float32 --size 16 --isa avx512 --stats", ".", true);
    if (wide.status == 0) CHECK(wide.out.find("compiled tapes AVX-512, float32 transcendentals AVX-512") != std::string::npos);
    else CHECK(wide.out == "fortu: error: --isa avx512: this CPU (or this build) has no AVX-512\n");
}
