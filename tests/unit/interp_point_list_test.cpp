// tests/unit/interp_point_list_test.cpp — arbitrary points through the voxel tape
// (point_list.hpp) give the grid's values bit for bit; CONSTANT values given to compile()
// (CompileOptions::constants) act as if the script had been written with them.
#include "interp/point_list.hpp"
#include "interp_test_support.hpp"

#include <doctest/doctest.h>

#include <cstring>
#include <vector>

using namespace fortu;
using fortu::test::compile_text;

namespace {

const char* kModel =
    "ARGUMENT X(-2, 2), Y(-1, 3);\n"
    "CONSTANT R = 0.6;\n"
    "VARIABLE D = R*R - X^2 - (Y - 1)^2;\n"
    "RETURN D & (Y - X^2) | SIN(3*X) / 4;\n";

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("points evaluated in tiles equal the grid, on any thread count") {
    auto c = compile_text(kModel);
    REQUIRE(c.model);
    const Grid grid = model_grid(*c.model, {37, 61, 1});   // 2257 points: two full tiles and a partial one
    const Field field = evaluate_grid(*c.model, grid, engine_named("voxel"));
    const PointListEvaluator points(c.model->graph, c.model->root);
    for (int threads : {1, 2, 3}) {
        std::vector<double> out(grid.points(), -1.0);
        EvalOptions options;
        options.threads = threads;
        points.values(grid.points(), [&](std::size_t first, int count, double* x, double* y, double* z) {
            for (int i = 0; i < count; ++i) {
                const std::size_t p = first + i;
                x[i] = grid.x_at(static_cast<int>(p % grid.cols()));
                y[i] = grid.y_at(static_cast<int>(p / grid.cols()));
                z[i] = 0.0;
            }
        }, out.data(), options);
        for (std::size_t p = 0; p < grid.points(); ++p) REQUIRE(same_bits(out[p], field.values[p]));
    }
    const double x = grid.x_at(5), y = grid.y_at(7);
    CHECK(same_bits(points.value({x, y, 0}), field.values[grid.index(5, 7)]));
    CHECK(same_bits(points.value({x, y, 0}), evaluate_point(*c.model, {x, y, 0}, engine_named("voxel")).value));
}

TEST_CASE("a CONSTANT given to compile() replaces the script's first top-level definition") {
    CompileOptions options;
    options.constants = {{"r", 0.8}};
    auto given = compile_text(kModel, options);
    auto written = compile_text(std::string(kModel).replace(std::string(kModel).find("0.6"), 3, "0.8"));
    REQUIRE(given.model);
    REQUIRE(written.model);
    for (double x : {-1.5, 0.0, 0.3})
        CHECK(same_bits(evaluate_point(*given.model, {x, 1.1, 0}, engine_named("voxel")).value,
                        evaluate_point(*written.model, {x, 1.1, 0}, engine_named("voxel")).value));
    CHECK(given.model->graph.size() == written.model->graph.size());   // folded alike

    SUBCASE("a FOR bound may be one") {
        CompileOptions n;
        n.constants = {{"N", 3}};
        auto loop = compile_text("ARGUMENT X, Y;\nCONSTANT N = 10;\nVARIABLE S = 0;\nFOR I = 1, N\n  S = S + X;\nEND FOR\nRETURN S;\n", n);
        REQUIRE(loop.model);
        CHECK(evaluate_point(*loop.model, {2, 0, 0}, engine_named("voxel")).value == 6.0);
    }
    SUBCASE("a name the script does not define is an error") {
        CompileOptions q;
        q.constants = {{"Q", 1}};
        auto missing = compile_text(kModel, q);
        CHECK_FALSE(missing.model);
        CHECK(missing.sink.render_all() == "error: cannot set 'Q': the script has no top-level CONSTANT of that name\n");
    }
}
