// tests/unit/cli_write_fault_test.cpp — a full disk never costs a file: every output format,
// run under an LD_PRELOAD shim (tests/fault/fail_write.cpp) that fails write(2) with ENOSPC
// after a few bytes, exits non-zero naming the path and the reason, leaves the previous file
// byte for byte and no temporary beside it. The formats come from the table, so a new row is
// tested without a new line here.
#include "cli_support.hpp"
#include "test_support.hpp"

#include "runtime/brick_output.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/temp_files.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include <unistd.h>

using fortu::test::quote;
using fortu::test::run_fortu;
using fortu::test::run_shell;
using namespace fortu;

namespace {

const char* kDisc = "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n";
const char* kBall = "ARGUMENT X, Y, Z;\nRETURN 0.25 - X*X - Y*Y - Z*Z;\n";

/// `fortu ARGS` in `dir` with write(2) to files failing after `bytes` bytes.
test::CommandResult run_on_full_disk(const std::string& args, const std::string& dir, int bytes) {
    return run_shell("cd " + quote(dir) + " && ASAN_OPTIONS=verify_asan_link_order=0 LD_PRELOAD=" +
                     quote(FORTU_FAIL_WRITE_SHIM) + " FORTU_FAIL_WRITE_AFTER=" + std::to_string(bytes) + " " +
                     quote(FORTU_BINARY) + " " + args + " 2>&1 >/dev/null");
}

std::vector<std::string> names_in(const test::ScratchDir& dir) {
    std::vector<std::string> out;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path)) out.push_back(entry.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("a full disk: every format fails with the OS reason, the old file intact, no temporary") {
    for (const OutputFormat& format : output_formats()) {
        for (std::string_view extension : format.extensions) {
            CAPTURE(extension);
            test::ScratchDir dir;
            const bool solid = format.kind == OutputKind::Mesh || format.kind == OutputKind::Volume;
            dir.write("m.fortu", solid ? kBall : kDisc);
            const std::string out = "out." + std::string(extension);
            const std::string small = solid ? "8x8x8" : "8";
            REQUIRE(run_fortu("run m.fortu --size " + small + " -o " + out, dir.path.string()).status == 0);
            const std::string before = dir.read(out);
            REQUIRE(!before.empty());
            for (int bytes : {0, 100}) {
                CAPTURE(bytes);
                const auto r = run_on_full_disk("run m.fortu --size " + std::string(solid ? "40x40x40" : "200") + " -o " + out,
                                                dir.path.string(), bytes);
                CHECK(r.status == 1);
                CHECK(dir.read(out) == before);
                if (brick_output_only(out)) {
                    // Written in bricks: the done map and partial files stay for --resume.
                    CHECK(r.out == "fortu: error: cannot write '" + out + ".done': No space left on device\n");
                    continue;
                }
                CHECK(r.out == "fortu: error: cannot write '" + out + "': No space left on device\n");
                CHECK(names_in(dir) == std::vector<std::string>{"m.fortu", out});
            }
        }
    }
}

TEST_CASE("a full disk: a multi-part 3D EXR (written by OpenEXR, not into memory) keeps the old file") {
    test::ScratchDir dir;
    dir.write("m.fortu", kBall);
    REQUIRE(run_fortu("run m.fortu --size 4x3x3 -o v.exr", dir.path.string()).status == 0);
    const std::string before = dir.read("v.exr");
    const auto r = run_on_full_disk("run m.fortu --size 30x30x30 -o v.exr", dir.path.string(), 300);
    CHECK(r.status == 1);
    CHECK(r.out.starts_with("fortu: error: cannot write 'v.exr': "));
    CHECK(dir.read("v.exr") == before);
    CHECK(names_in(dir) == std::vector<std::string>{"m.fortu", "v.exr"});
}

TEST_CASE("a full disk: --mimages and --contour keep their old files too") {
    test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    REQUIRE(run_fortu("run m.fortu --size 8 -o v.npy --mimages m_%d.png --contour c.svg", dir.path.string()).status == 0);
    const std::string m1 = dir.read("m_1.png"), contour = dir.read("c.svg");
    const auto r = run_on_full_disk("run m.fortu --size 100 --mimages m_%d.png --contour c.svg", dir.path.string(), 50);
    CHECK(r.status == 1);
    CHECK(r.out.find("No space left on device") != std::string::npos);
    CHECK(dir.read("m_1.png") == m1);
    CHECK(dir.read("c.svg") == contour);
    for (const std::string& name : names_in(dir)) CHECK_FALSE(temporary_file_owner(name));
}

TEST_CASE("temporary names carry the pid; the next run removes those of dead processes") {
    const std::string name = temporary_file_name("out.tmp7-abcdef.png", "x1y2z3");
    CHECK(name == ".out.tmp7-abcdef.png.tmp" + std::to_string(::getpid()) + "-x1y2z3.png");
    CHECK(temporary_file_owner(name) == ::getpid());
    CHECK(temporary_file_owner(".a.csv.tmp12-abc123.csv") == 12);
    CHECK(temporary_file_owner(".a.tmp12-abc123") == 12);
    CHECK_FALSE(temporary_file_owner("a.csv.tmp12-abc123.csv"));   // not hidden: a user's file
    CHECK_FALSE(temporary_file_owner(".a.csv.tmp12.csv"));
    CHECK_FALSE(temporary_file_owner(".a.csv.tmpx-abc123.csv"));
    CHECK_FALSE(temporary_file_owner(".a.csv.tmp12-ab.csv"));

    test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    // pid 2^22 + 1 is above Linux's pid_max limit, so no process has it.
    dir.write(".out.npy.tmp4194305-abc123.npy", "stale");
    dir.write(".other.csv.tmp4194305-zzz999.csv", "stale");
    const std::string alive = ".out.npy.tmp1-abc123.npy";   // pid 1 always exists
    dir.write(alive, "someone else's, in progress");
    REQUIRE(run_fortu("run m.fortu --size 8 -o out.npy", dir.path.string()).status == 0);
    CHECK(names_in(dir) == std::vector<std::string>{alive, "m.fortu", "out.npy"});
}
