// tests/unit/cli_repl_test.cpp — `fortu repl` scripted through stdin (not a terminal: no
// prompt, no colour, deterministic output): a model built in steps, probed, changed and saved,
// the saved script giving `fortu run` the same image as :render; errors that do not end the
// session; the ASCII picture of :show. The interactive side is tests/repl/ (tmux).
#include "cli_support.hpp"
#include "test_support.hpp"

#include "runtime/image_io.hpp"
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using fortu::test::quote;
using fortu::test::run_fortu;
using fortu::test::run_shell;
namespace fs = std::filesystem;

namespace {

struct SessionDir : fortu::test::ScratchDir {
    /// `fortu repl ARGS < session.txt` in this folder, HOME pointing here; stdout and stderr.
    fortu::test::CommandResult repl(const std::string& input, const std::string& args = "") const {
        write("session.txt", input);
        return run_shell("cd " + quote(path.string()) + " && HOME=" + quote(path.string()) + " " +
                         quote(FORTU_BINARY) + " repl " + args + " < session.txt 2>&1");
    }
};

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::vector<float> pixels(const std::string& path) {
    std::string error;
    auto image = fortu::read_image(path, error);
    REQUIRE_MESSAGE(image, error);
    return image->pixels;
}

/// The model both scripted sessions start from: a disc or a bar, on a 64×48 grid.
constexpr const char* kDiscOrBar =
    "ARGUMENT X, Y\n"
    "CONSTANT R = 0.5\n"
    "VARIABLE D = R - SQRT(X^2 + Y^2)\n"
    "VARIABLE B = 0.3 - ABS(X - 0.5)\n"
    "RETURN D | B\n"
    ":size 64 48\n";

}  // namespace

TEST_CASE("a scripted session: built in steps, probed, changed, saved; fortu run gives the same image") {
    SessionDir d;
    const auto r = d.repl(std::string(kDiscOrBar) +
        ":eval 0.25 0\n"
        "D\n"
        ":render before.png\n"
        "R = 0.3\n"
        ":eval 0.25 0\n"
        "D\n"
        ":save session.fortu\n"
        ":render after.png\n"
        ":quit\n"
        "this line is never read\n");
    CHECK(r.status == 0);
    CHECK(r.out ==
          "size: 64x48\n"
          "value: 0.5549509756796392\n"
          "gradient: -0.7844645405527362 0\n"
          "normal: n1=0.48367098178501616 n2=0.11737271157899065 n3=0.7014307126275634 n4=-0.5101774037905854\n"
          "inside: yes\n"
          "0.25\n"
          "wrote before.png (64x48)\n"
          "replaced R\n"
          "value: 0.1707106781186547\n"
          "gradient: 0 0\n"
          "normal: n1=-0.37615228230974446 n2=0.130988311682174 n3=0.9151417240802378 n4=-0.06218639371497618\n"
          "inside: yes\n"
          "0.04999999999999999\n"
          "saved session.fortu\n"
          "wrote after.png (64x48)\n");
    CHECK(d.read("session.fortu") ==
          "// A fortu repl session, saved with :save.\n"
          "RECTBMP(64, 48)\n"
          "ARGUMENT X(-1, 1), Y(-1, 1)\n"
          "CONSTANT R = 0.3\n"
          "VARIABLE D = R - SQRT(X^2 + Y^2)\n"
          "VARIABLE B = 0.3 - ABS(X - 0.5)\n"
          "RETURN D | B\n");
    const auto run = run_fortu("run session.fortu -o run.png", d.path.string());
    REQUIRE(run.status == 0);
    const auto after = pixels((d.path / "after.png").string());
    CHECK(after.size() == 64u * 48u * 3u);
    CHECK(pixels((d.path / "run.png").string()) == after);
    // The new radius did change the picture.
    CHECK(pixels((d.path / "before.png").string()) != after);
    // Loaded back, the saved session gives the same values.
    const auto again = d.repl(":eval 0.25 0\n", "session.fortu");
    CHECK(again.out == "loaded session.fortu (6 statements)\n"
                       "value: 0.1707106781186547\n"
                       "gradient: 0 0\n"
                       "normal: n1=-0.37615228230974446 n2=0.130988311682174 n3=0.9151417240802378 n4=-0.06218639371497618\n"
                       "inside: yes\n");
}

TEST_CASE(":time says what the last evaluation computed and which definitions' values it reused") {
    SessionDir d;
    const auto r = d.repl(std::string(kDiscOrBar) +
        ":render a.png\n"
        "R = 0.3\n"
        ":render b.png\n"
        ":time\n"
        "R = 0.5\n"
        ":render c.png\n"
        ":time\n");
    CHECK(r.status == 0);
    // Times vary; everything else is exact. D uses R: its 5 operations and the | are
    // computed again, B's 3 are read.
    std::istringstream lines(r.out);
    std::vector<std::string> last;
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("last evaluation: ", 0) == 0) last.push_back(line);
    REQUIRE(last.size() == 2);
    CHECK(last[0].rfind("last evaluation: voxel engine, 64x48 points; computed 6 of 9 operations in ", 0) == 0);
    CHECK(last[0].find(" s; reused the kept values of 1 definition (B); kept the values of 1 definition for next time") !=
          std::string::npos);
    CHECK(last[1] == "last evaluation: voxel engine, 64x48 points; reused: the values of this model on this grid "
                     "were kept, nothing was evaluated");
    CHECK(pixels((d.path / "a.png").string()) == pixels((d.path / "c.png").string()));
}

TEST_CASE("errors are file diagnostics of the typed line and the session goes on") {
    SessionDir d;
    const auto r = d.repl(
        ":show\n"
        "ARGUMENT X, Y\n"
        "RETURN 0.5 - SQRT(X^2 + Y^2\n"
        "RETURN 0.5 - SQRT(X^2 + Q)\n"
        "RETURN 0.5 - SQRT(X^2 + Y^2)\n"
        ":eval 1\n"
        ":eval 0 zero\n"
        ":render out.xyz\n"
        ":save no/such/dir/x.fortu\n"
        ":engine turbo\n"
        ":rsystem alpha=3\n"
        ":domain 1 0 0 1\n"
        ":size 0\n"
        ":frobnicate\n"
        ":load missing.fortu\n"
        ":eval 0 0.5\n");
    CHECK(r.status == 1);   // a scripted session with errors fails, after running to the end
    CHECK(r.out ==
          "fortu: error: there is no model yet\n"
          "note: type RETURN and an expression (after ARGUMENT X, Y and your definitions)\n"
          "<input>:1:28: error: unexpected end of file, expecting operator, ',' or ')'\n"
          "RETURN 0.5 - SQRT(X^2 + Y^2\n"
          "                           ^\n"
          "<input>:1:18: note: to match this '('\n"
          "RETURN 0.5 - SQRT(X^2 + Y^2\n"
          "                 ^\n"
          "<input>:1:25: error: unknown name 'Q'\n"
          "RETURN 0.5 - SQRT(X^2 + Q)\n"
          "                        ^\n"
          "fortu: error: :eval: the model has 2 argument(s); give 2 coordinate(s)\n"
          "fortu: error: :eval: 'zero' is not a finite coordinate\n"
          "fortu: error: :render: cannot write 'out.xyz': the extension is not one of png, jpg, jpeg, tif, tiff, bmp, exr, npy, csv, svg, stl, obj, ply, vti, nrrd, vdb, pvti, hdf, vtkhdf\n"
          "fortu: error: cannot write 'no/such/dir/x.fortu': directory 'no/such/dir' does not exist\n"
          "fortu: error: :engine: 'turbo' is not classic or voxel\n"
          "fortu: error: :rsystem: 'alpha=3' is not r0, minmax, r1 or alpha=A with A in (-1, 1]\n"
          "fortu: error: :domain: 1 must be less than 0\n"
          "fortu: error: :size: '0' is not a node count from 2 to 1000000\n"
          "fortu: error: unknown command ':frobnicate'\n"
          "note: :help lists the commands\n"
          "fortu: error: cannot read 'missing.fortu': No such file or directory\n"
          "value: 0\n"
          "gradient: 0 -1\n"
          "normal: n1=0.005228365101232297 n2=0.666657554670518 n3=0.666657554670518 n4=-0.333328777335259\n"
          "inside: boundary\n");
    // Not a terminal: no history file is written.
    CHECK_FALSE(fs::exists(d.path / ".fortu_history"));
}

TEST_CASE("blocks over several lines, settings, and a bare expression at the probe point") {
    SessionDir d;
    const auto r = d.repl(
        "ARGUMENT X, Y\n"
        "FUNCTION BOX(A, B)\n"
        "  W = A - ABS(X)\n"
        "  H = B - ABS(Y)\n"
        "  RETURN W & H\n"
        "END\n"
        "VARIABLE S = 0\n"
        "FOR I = 1, 3\n"
        "  S = S + I\n"
        "END FOR\n"
        "RETURN BOX(0.5, S / 10)\n"
        ":eval 0.25 0\n"
        "S\n"
        ":rsystem minmax\n"
        ":rsystem\n"
        "RETURN\n"
        ":domain 0 2 -1 1\n"
        ":domain\n"
        ":size 10x20\n"
        ":size\n"
        ":engine classic\n"
        ":engine\n"
        "BOX(1, 1) + X\n"
        ":reset\n"
        ":domain\n"
        "S\n");
    CHECK(r.out ==
          "value: 0.19999999999999996\n"
          "gradient: -0.6153846153846154 -0.0769230769230771\n"
          "normal: n1=0.5037859903140264 n2=0.06318186452848372 n3=0.8118390183144126 n4=-0.28831430124138985\n"
          "inside: yes\n"
          "6\n"
          "rsystem: MINMAX\n"
          "<input>:1:7: error: unexpected end of file, expecting expression\n"
          "RETURN\n"
          "      ^\n"
          "domain: x [0, 2], y [-1, 1]\n"
          "size: 10x20\n"
          "size: 10x20\n"
          "engine: classic\n"
          "1\n"
          "domain: x [-1, 1], y [-1, 1]\n"
          "<input>:1:1: error: unknown name 'S'\n"
          "S\n"
          "^\n");
}

TEST_CASE(":show without a terminal draws the disc in ASCII, sized to 80x24") {
    SessionDir d;
    const auto r = d.repl("ARGUMENT X, Y\nRETURN 0.5 - SQRT(X^2 + Y^2)\n:domain -1 1 -0.5 0.5\n:show\n");
    CHECK(r.out ==
          "................................****************................................\n"
          ".............................***################***.............................\n"
          "..........................***######################***..........................\n"
          "........................**############################**........................\n"
          ".......................**##############################**.......................\n"
          "......................*##################################*......................\n"
          ".....................*####################################*.....................\n"
          "....................**####################################**....................\n"
          "....................*######################################*....................\n"
          "....................*######################################*....................\n"
          "....................*######################################*....................\n"
          "....................*######################################*....................\n"
          "....................**####################################**....................\n"
          ".....................*####################################*.....................\n"
          "......................*##################################*......................\n"
          ".......................**##############################**.......................\n"
          "........................**############################**........................\n"
          "..........................***######################***..........................\n"
          ".............................***################***.............................\n"
          "................................****************................................\n"
          "x [-1, 1], y [-0.5, 0.5]; # inside, . outside, * contour\n");
}

TEST_CASE("fortu repl usage errors exit 2") {
    CHECK(run_fortu("repl a.fortu b.fortu").status == 2);
    CHECK(run_fortu("repl a.fortu b.fortu").out ==
          "fortu: error: 'fortu repl' takes one model at most\n"
          "usage: fortu repl [MODEL.fortu]\n"
          "  an interactive session: type FORTU statements and :commands (:help lists them)\n");
    CHECK(run_fortu("repl --frob").out == "fortu: error: unknown option '--frob'\nsee fortu repl --help\n");
    CHECK(run_fortu("repl --help", ".", true).status == 0);
}

TEST_CASE(":load of /dev/zero or of an INCLUDE chain thousands deep is an error, and the session goes on") {
    SessionDir d;
    for (int i = 0; i < 3000; ++i) d.write("l" + std::to_string(i) + ".fortu", "INCLUDE 'l" + std::to_string(i + 1) + ".fortu';\n");
    d.write("l3000.fortu", "CONSTANT C = 1;\n");
    d.write("deep.fortu", "ARGUMENT X, Y;\nINCLUDE 'l0.fortu';\nRETURN X + Y + C;\n");
    const auto r = d.repl(":load /dev/zero\n:load deep.fortu\nARGUMENT X, Y\nRETURN X + Y\n:eval 1 2\n");
    CHECK(r.status == 1);
    CHECK(r.out == "fortu: error: cannot read '/dev/zero': not a regular file\n"
                   "l62.fortu:1:1: error: INCLUDE nests more than 64 files deep\n"
                   "INCLUDE 'l63.fortu';\n"
                   "^~~~~~~~~~~~~~~~~~~\n"
                   "note: the limit 'include-depth' is 64; raise it with --limit include-depth=N\n"
                   "value: 3\n"
                   "gradient: 1 1\n"
                   "normal: n1=-0.577350269189615 n2=-0.5773502691896312 n3=0.5773502691896312 n4=-3.1260162170523e-12\n"
                   "inside: yes\n");
}

TEST_CASE("a classic :render over fortu run's budget is refused before it starts, as fortu run refuses it") {
    SessionDir d;
    d.write("nested.fortu", fortu::test::read_file(std::string(FORTU_SOURCE_DIR) + "/examples/nested_discs.fortu"));
    // 135,144 operations per point x 300² points = 1.2e10, over the 1e10 fortu run allows.
    const auto r = d.repl(":load nested.fortu\n:engine classic\n:size 300\n:render big.png\n:size 10\n:time\n");
    CHECK(r.status == 1);
    CHECK(r.out.starts_with(
          "loaded nested.fortu (5 statements)\n"
          "size: 300x300\n"
          "fortu: error: the classic engine would need 135,144 operations per point x 90,000 points = 1.22e+10 "
          "operations (budget 1e+10)\n"
          "note: use :engine voxel or a smaller :size\n"
          "size: 10x10\n"
          "last evaluation: none of this model yet (:show and :render evaluate it)\n"
          "the whole model, nothing reused:\n"
          "classic: 10x10 points in "));
    CHECK_FALSE(fs::exists(d.path / "big.png"));
    const auto run = run_fortu("run nested.fortu --engine classic --size 300 -o big.png", d.path.string());
    CHECK(run.status == 2);
    CHECK(run.out.find("= 1.22e+10 operations (budget 1e+10)") != std::string::npos);
}

TEST_CASE(":time after a new RETURN says there is no evaluation of it yet, then times it") {
    SessionDir d;
    const auto r = d.repl("ARGUMENT X, Y\nRETURN 0.5 - X\n:size 8\n:render a.npy\n:time\nRETURN 0.4 - X\n:time\n"
                          ":render b.npy\n:time\n");
    CHECK(r.status == 0);
    std::istringstream lines(r.out);
    std::vector<std::string> last;
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("last evaluation: ", 0) == 0) last.push_back(line);
    REQUIRE(last.size() == 3);
    CHECK(last[0].starts_with("last evaluation: voxel engine, 8x8 points; computed 1 of 1 operations in "));
    CHECK(last[1] == "last evaluation: none of this model yet (:show and :render evaluate it)");
    CHECK(last[2].starts_with("last evaluation: voxel engine, 8x8 points; computed 1 of 1 operations in "));
}

TEST_CASE(":size confirms the grid; one number gives square cells on the domain, as fortu run --size") {
    SessionDir d;
    const auto r = d.repl("ARGUMENT X, Y, Z\nRETURN 1 - X^2/64 - Y^2/25 - Z^2/64\n:size 512\n:domain -8 8 -5 5 -8 8\n"
                          ":size 96\n:size 20 10 5\n:size default\n:render cube.npy\n");
    CHECK(r.status == 0);
    // 96 nodes along X's 16 units: 16/95 per cell, so Y's 10 units take 60 cells (widened to 10.1).
    CHECK(r.out == "size: 512x512x512\n"
                   "size: 96x61x96\n"
                   "size: 20x10x5\n"
                   "size: 64x64x64\n"   // no size: 64 nodes per axis, as fortu run
                   "wrote cube.npy (64x64x64)\n");
    const auto run = run_fortu("run m.fortu --domain -8:8,-5:5,-8:8 --size 96 -o r.npy --stats",
                               (d.write("m.fortu", "ARGUMENT X, Y, Z\nRETURN 1 - X^2/64 - Y^2/25 - Z^2/64\n"), d.path.string()), true);
    CHECK(run.out.find("96x61x96") != std::string::npos);
}

TEST_CASE(":show and :render of a 3D model: a plane with --slice, a shaded view with --view, as fortu run") {
    SessionDir d;
    const auto r = d.repl("ARGUMENT X, Y, Z\nRETURN 0.5 - SQRT(X^2 + Y^2 + Z^2)\n:size 9\n"
                          ":render s.png --slice x=0.25\n"
                          ":render z.npy --slice 4\n"
                          ":render v.png --view top\n"
                          ":render w.png\n"
                          ":render bad.png --slice x=3\n"
                          ":render bad.npy --view top\n"
                          ":show --view front --slice z=0\n"
                          ":show --view sideways\n");
    CHECK(r.status == 1);
    CHECK(r.out == "size: 9x9x9\n"
                   "wrote s.png (1x9x9, x = 0.25, y [-1, 1], z [-1, 1])\n"
                   "wrote z.npy (9x9x1, x [-1, 1], y [-1, 1], z = 0)\n"
                   "wrote v.png (9x9 shaded view, azimuth 0, elevation 90, y up)\n"
                   "wrote w.png (9x9 shaded view, azimuth 45, elevation 35.264389682754654, y up)\n"
                   "fortu: error: --slice: x=3 is outside the domain's X [-1, 1]\n"
                   "fortu: error: :render: a shaded view is a picture; 'bad.npy' is not one\n"
                   "fortu: error: :show: a picture is a plane (--slice) or a shaded view (--view, --up), not both\n"
                   "fortu: error: :show: --view: 'sideways' is not top, front, side, iso or AZ,EL in degrees\n");
    for (const char* file : {"s.png", "z.npy", "v.png", "w.png"}) CHECK(fs::exists(d.path / file));
    // The plane x = 0.25 is the same picture fortu run --slice draws.
    const auto run = run_fortu("run m.fortu --size 9 --slice x=0.25 -o run.png",
                               (d.write("m.fortu", "ARGUMENT X, Y, Z\nRETURN 0.5 - SQRT(X^2 + Y^2 + Z^2)\n"), d.path.string()));
    REQUIRE(run.status == 0);
    CHECK(pixels((d.path / "run.png").string()) == pixels((d.path / "s.png").string()));

    // In the terminal (80x24 without one): the plane z = 0 is a disc, the shaded view a ball.
    const auto plane = d.repl("ARGUMENT X, Y, Z\nRETURN 0.5 - SQRT(X^2 + Y^2 + Z^2)\n:show --slice z=0\n");
    const auto plane_lines = lines_of(plane.out);
    REQUIRE(plane_lines.size() == 23);   // 44 pixel rows of a square plane: 22 lines, then the caption
    CHECK(plane_lines[22] == "x [-1, 1], y [-1, 1], z = 0; # inside, . outside, * contour");
    CHECK(plane_lines[0] == std::string(44, '.'));
    CHECK(plane_lines[11].find('#') != std::string::npos);
    const auto side = lines_of(d.repl("ARGUMENT X, Y, Z\nRETURN 0.5 - SQRT(X^2 + Y^2 + Z^2)\n:show --slice y=0\n").out);
    REQUIRE(side.size() == 23);
    CHECK(side[22] == "x [-1, 1], y = 0, z [-1, 1]; # inside, . outside, * contour");
    CHECK(side[11] == plane_lines[11]);   // the same disc, across X and up Z
    const auto ball = d.repl("ARGUMENT X, Y, Z\nRETURN 0.5 - SQRT(X^2 + Y^2 + Z^2)\n:show --view front\n:show\n");
    const auto ball_lines = lines_of(ball.out);
    REQUIRE(ball_lines.size() == 46);
    CHECK(ball_lines[22] == "x [-1, 1], y [-1, 1], z [-1, 1]; shaded view, azimuth 0, elevation 0, y up; "
                            "# surface, + cut by the domain");
    CHECK(ball_lines[45] == "x [-1, 1], y [-1, 1], z [-1, 1]; shaded view, azimuth 45, elevation 35.264389682754654, "
                            "y up; # surface, + cut by the domain");
    CHECK(ball_lines[11].find('#') != std::string::npos);
    CHECK(ball_lines[0].find('#') == std::string::npos);
    for (std::size_t i = 0; i < ball_lines.size(); ++i)   // the ball is inside the domain: no cut face
        if (i != 22 && i != 45) CHECK(ball_lines[i].find('+') == std::string::npos);
}

TEST_CASE("2D models take no --slice or --view; :render's file name may hold spaces") {
    SessionDir d;
    const auto r = d.repl("ARGUMENT X, Y\nRETURN 0.5 - X\n:size 8\n:render my picture.png\n:render a.png --slice z=0\n"
                          ":show --up z\n:render a.png --slice\n");
    CHECK(r.out == "size: 8x8\n"
                   "wrote my picture.png (8x8)\n"
                   "fortu: error: :render: --slice, --view and --up draw 3D models; this one has 2 argument(s)\n"
                   "fortu: error: :show: --slice, --view and --up draw 3D models; this one has 2 argument(s)\n"
                   "fortu: error: :render: --slice needs a value\n");
    CHECK(fs::exists(d.path / "my picture.png"));
}
