// tests/unit/cli_run_checks_test.cpp — `fortu run` refuses, before evaluating anything, the
// runs that would end in a partial result: an output whose folder is missing, two outputs
// naming one file, a grid whose field and writers exceed the memory available.
#include "cli_support.hpp"
#include "test_support.hpp"

#include "cli/run_checks.hpp"

#include <doctest/doctest.h>

using fortu::test::run_fortu;
using namespace fortu;

namespace {

const char* kDisc = "ARGUMENT X, Y;\nRETURN 0.25 - X*X - Y*Y;\n";

Grid grid_of(int cols, int rows, int slices = 1) {
    Grid g;
    g.dims = slices > 1 ? 3 : 2;
    g.x.nodes = cols;
    g.y.nodes = rows;
    g.z.nodes = slices;
    return g;
}

}  // namespace

TEST_CASE("run checks: a bad --mimages or --contour folder is found before the main output is written") {
    test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    const auto mimages = run_fortu("run m.fortu --size 8 -o out.png --mimages nodir/m_%d.png", dir.path.string());
    CHECK(mimages.status == 1);
    CHECK(mimages.out == "fortu: error: cannot write 'nodir/m_1.png': directory 'nodir' does not exist\n");
    const auto contour = run_fortu("run m.fortu --size 8 -o out.png --contour m.fortu/c.svg", dir.path.string());
    CHECK(contour.status == 1);
    CHECK(contour.out == "fortu: error: cannot write 'm.fortu/c.svg': 'm.fortu' is not a directory\n");
    CHECK(dir.entries() == 1);   // no out.png
}

TEST_CASE("run checks: two outputs naming one file are a usage error, nothing written") {
    test::ScratchDir dir;
    dir.write("m.fortu", kDisc);
    const auto r = run_fortu("run m.fortu --size 8 -o m_1.png --mimages m_%d.png", dir.path.string());
    CHECK(r.status == 2);
    CHECK(r.out == "fortu: error: -o and --mimages would both write 'm_1.png'\n");
    const auto same = run_fortu("run m.fortu --size 8 -o c.svg --contour ./c.svg", dir.path.string());
    CHECK(same.status == 2);
    CHECK(same.out == "fortu: error: -o and --contour would both write './c.svg'\n");
    CHECK(dir.entries() == 1);
}

TEST_CASE("run checks: the files of each output, series expanded") {
    CliOptions o;
    o.output = "s_%d.png";
    o.mimages = "m_%d.png";
    o.contour = "c.svg";
    std::vector<std::string> paths;
    for (const PlannedFile& f : planned_files(o, grid_of(4, 4, 3))) paths.push_back(f.option + " " + f.path);
    CHECK(paths == std::vector<std::string>{"-o s_0.png", "-o s_1.png", "-o s_2.png", "--mimages m_1.png",
                                            "--mimages m_2.png", "--mimages m_3.png", "--mimages m_4.png",
                                            "--mimages m_5.png", "--contour c.svg"});
}

TEST_CASE("run checks: a run above the memory available is refused with the estimate, unless --force") {
    CliOptions o;
    o.output = "v.exr";
    const Grid g = grid_of(645, 645, 645);
    // 268,336,125 points: 8 bytes of field each, and the EXR's float channels (6 x 4 bytes, twice).
    CHECK(estimated_run_bytes(o, g) == std::size_t{268'336'125} * (8 + 48));
    CHECK_THROWS_WITH_AS(check_memory(o, g, std::size_t{8} << 30),
                         "the run needs about 14.0 GiB of memory (268,336,125 points and its outputs), more than "
                         "the 8.0 GiB available\nnote: use a smaller --size, fewer outputs, or --force",
                         UsageError);
    CHECK_NOTHROW(check_memory(o, g, std::size_t{16} << 30));
    o.force = true;
    CHECK_NOTHROW(check_memory(o, g, std::size_t{8} << 30));
}

TEST_CASE("run checks: --force does not let the classic engine recurse 100,000 levels deep (a stack overflow)") {
    test::ScratchDir dir;
    dir.write("deep.fortu", "ARGUMENT X, Y;\nVARIABLE S = 0;\nFOR I = 1, 100000\nVARIABLE S = S + X * I;\nEND FOR\n"
                            "RETURN S - Y;\n");
    const auto r = run_fortu("run deep.fortu --size 8 --engine classic --force", dir.path.string());
    CHECK(r.status == 2);
    CHECK(r.out == "fortu: error: the model is nested 100003 levels deep; the classic engine's recursion stops at "
                   "20000\nnote: use --engine voxel\n");
}
