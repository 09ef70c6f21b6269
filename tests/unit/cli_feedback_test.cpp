// tests/unit/cli_feedback_test.cpp — what a finished `fortu run` says (one `wrote FILE (SIZE)`
// line per file on standard error, --quiet to silence), and that what can be checked before
// evaluating is: a note printed after the evaluation (invalid points) must not appear.
#include "cli_support.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

using fortu::test::run_fortu;

namespace {

const char* kDisc = "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n";
const char* kBall = "ARGUMENT X, Y, Z;\nRETURN 0.25 - X*X - Y*Y - Z*Z;\n";
/// Every point invalid: the evaluation ends with `fortu: note: N invalid points`.
const char* kInvalid = "ARGUMENT X, Y;\nRETURN SQRT(-1 - X*X);\n";

}  // namespace

TEST_CASE("feedback: a 2D run says each file it wrote, --mimages and --contour included") {
    fortu::test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    const auto r = run_fortu("run m.fortu --size 8 -o a.png --mimages m_%d.png --contour c.svg", dir.path.string());
    CHECK(r.status == 0);
    CHECK(r.out == "wrote a.png (8x8)\nwrote m_1.png (8x8)\nwrote m_2.png (8x8)\nwrote m_3.png (8x8)\n"
                   "wrote m_4.png (8x8)\nwrote c.svg (8x8)\n");
    const auto quiet = run_fortu("run m.fortu --size 8 -o a.png --contour c.svg -q", dir.path.string());
    CHECK(quiet.status == 0);
    CHECK(quiet.out == "");
    CHECK(run_fortu("run m.fortu --size 8 -o a.npy --quiet", dir.path.string()).out == "");
}

TEST_CASE("feedback: 3D values and volumes give the grid, series one line per slice, views and meshes their size") {
    fortu::test::ScratchDir dir;
    dir.write("b.fortu", kBall);
    const std::string cwd = dir.path.string();
    CHECK(run_fortu("run b.fortu --size 4 -o v.npy", cwd).out == "wrote v.npy (4x4x4)\n");
    CHECK(run_fortu("run b.fortu --size 4 -o v.vti --mimages m.exr", cwd).out ==
          "wrote v.vti (4x4x4)\nwrote m.exr (4x4x4)\n");
    CHECK(run_fortu("run b.fortu --size 3 -o s_%d.png", cwd).out ==
          "wrote s_0.png (3x3)\nwrote s_1.png (3x3)\nwrote s_2.png (3x3)\n");
    CHECK(run_fortu("run b.fortu --size 20x10 -o view.png", cwd).out == "wrote view.png (20x10)\n");
    CHECK(run_fortu("run b.fortu --size 10 --slice x=0 -o x.png", cwd).out == "wrote x.png (10x10)\n");
    CHECK(run_fortu("run b.fortu --size 10 -o m.stl", cwd).out == "wrote m.stl (600 triangles)\n");
    CHECK(run_fortu("run b.fortu --size 10 -o m.stl -q", cwd).out == "");
}

TEST_CASE("feedback: a missing output folder fails before the evaluation") {
    fortu::test::ScratchDir dir;
    dir.write("bad.fortu", kInvalid);
    const auto r = run_fortu("run bad.fortu --engine classic --size 100 -o /nonexistent/x.png", dir.path.string());
    CHECK(r.status == 1);
    CHECK(r.out == "fortu: error: cannot write '/nonexistent/x.png': directory '/nonexistent' does not exist\n");
    // The reproducer, a 15 s classic evaluation had it been evaluated first.
    const auto nested = run_fortu("run " + std::string(FORTU_SOURCE_DIR) +
                                  "/examples/nested_discs.fortu --engine classic --size 100 -o /nonexistent/x.png");
    CHECK(nested.status == 1);
    CHECK(nested.out == "fortu: error: cannot write '/nonexistent/x.png': directory '/nonexistent' does not exist\n");
    // The check itself is not after the evaluation: the invalid-points note would come first.
    const auto after = run_fortu("run bad.fortu --size 4 -o ok.npy", dir.path.string());
    CHECK(after.out == "fortu: note: 16 invalid points (non-finite values)\nwrote ok.npy (4x4)\n");
}

TEST_CASE("feedback: --slice on a 2D model is a usage error before the evaluation, for run and singular") {
    fortu::test::ScratchDir dir;
    dir.write("bad.fortu", kInvalid);
    const std::string message = "fortu: error: --slice: the model has 2 arguments; slices are planes of 3D models\n";
    const auto run = run_fortu("run bad.fortu --slice 5 -o x.png", dir.path.string());
    CHECK(run.status == 2);
    CHECK(run.out == message);
    const auto singular = run_fortu("singular bad.fortu --slice 5", dir.path.string(), true);
    CHECK(singular.status == 2);
    CHECK(singular.out == message);
    const auto folder = run_fortu("singular bad.fortu -o /nonexistent/s.png", dir.path.string(), true);
    CHECK(folder.status == 1);
    CHECK(folder.out == "fortu: error: cannot write '/nonexistent/s.png': directory '/nonexistent' does not exist\n");
    CHECK(dir.entries() == 1);
}
