// tests/unit/runtime_grid_test.cpp — the grid convention (fortu-language.md §2): nodes include
// both ends, row 0 is the largest Y, column 0 the smallest X, slice 0 the smallest Z.
#include "runtime/field.hpp"
#include "runtime/grid.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>

using namespace fortu;

TEST_CASE("RECTANGLE(-1,-1,1,1) RECTBMP(3,3) with y+x gives rows 0 1 2 / -1 0 1 / -2 -1 0") {
    Field f;
    f.grid.x = {-1.0, 1.0, 3};
    f.grid.y = {-1.0, 1.0, 3};
    f.values.resize(f.grid.points());
    for (int r = 0; r < f.grid.rows(); ++r)
        for (int c = 0; c < f.grid.cols(); ++c) f.values[f.grid.index(c, r)] = f.grid.y_at(r) + f.grid.x_at(c);

    CHECK(f.grid.points() == 9);
    CHECK(f.values == std::vector<double>{0, 1, 2, -1, 0, 1, -2, -1, 0});
    CHECK(f.grid.x_at(0) == -1.0);
    CHECK(f.grid.x_at(2) == 1.0);
    CHECK(f.grid.y_at(0) == 1.0);
    CHECK(f.grid.y_at(2) == -1.0);
    CHECK(f.grid.index(2, 1) == 5);
    CHECK(f.invalid_count() == 0);
}

TEST_CASE("3D index order is slice, row, col and slice 0 is the smallest Z") {
    Grid g;
    g.dims = 3;
    g.x = {0.0, 1.0, 2};
    g.y = {0.0, 1.0, 3};
    g.z = {-2.0, 2.0, 5};
    CHECK(g.points() == 30);
    CHECK(g.index(1, 2, 4) == (4 * 3 + 2) * 2 + 1);
    CHECK(g.z_at(0) == -2.0);
    CHECK(g.z_at(4) == 2.0);
    CHECK(g.z.step() == 1.0);
}

TEST_CASE("a single-node axis sits at its minimum (x, z) or maximum (y) and has step 0") {
    Grid g;
    g.x = {0.5, 2.0, 1};
    g.y = {-3.0, 4.0, 1};
    CHECK(g.x.step() == 0.0);
    CHECK(g.x_at(0) == 0.5);
    CHECK(g.y_at(0) == 4.0);
    CHECK(g.slices() == 1);
}

TEST_CASE("non-finite values are invalid points") {
    Field f;
    f.grid.x = {0.0, 1.0, 4};
    f.values = {1.0, std::nan(""), std::numeric_limits<double>::infinity(), -2.0};
    CHECK(f.invalid_count() == 2);
}
