// tests/unit/interp_written_r_operations_test.cpp — R0 written out as a formula is found in
// each of its spellings (and not in near misses), becomes the R-operation with the same
// values bit for bit, and lets the pruned sign renderer decide what it could not before.
#include "interp_test_support.hpp"

#include "interp/sign_render.hpp"
#include "interp/written_r_operations.hpp"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <random>

using namespace fortu;

namespace {

/// The R-operations (RAnd, ROr) in the tape pruning_tape gives for `text`.
struct Counted {
    int conjunctions = 0, disjunctions = 0;
};
Counted r_operations_in(const std::string& text) {
    test::Compiled c = test::compile_text(text);
    REQUIRE(c.model);
    Counted n;
    for (const Instruction& ins : pruning_tape(c.model->graph, c.model->root).code) {
        n.conjunctions += ins.op == ir::Op::RAnd;
        n.disjunctions += ins.op == ir::Op::ROr;
    }
    return n;
}

}  // namespace

TEST_CASE("written R0 is found in each of its spellings") {
    auto found = [](const std::string& body) {
        const Counted n = r_operations_in("ARGUMENT X, Y, Z\nVARIABLE A = 1 - X*X;\nVARIABLE B = Y - Z;\nRETURN " + body);
        return std::pair{n.conjunctions, n.disjunctions};
    };
    CHECK(found("A + B - SQRT(A*A + B*B)") == std::pair{1, 0});
    CHECK(found("B + A - SQRT(A*A + B*B)") == std::pair{1, 0});
    CHECK(found("A + B - SQRT(B^2 + A^2)") == std::pair{1, 0});
    CHECK(found("A + B + SQRT(A*A + B*B)") == std::pair{0, 1});
    CHECK(found("SQRT(A*A + B*B) + (A + B)") == std::pair{0, 1});
    // Nested, as RANOK scripts chain them: (A ∧ B) ∨ X.
    CHECK(found("(A + B - SQRT(A*A + B*B)) + X + SQRT((A + B - SQRT(A*A + B*B))^2 + X*X)") == std::pair{1, 1});
    // Near misses: another operand under the root, a product for a square, a difference.
    CHECK(found("A + B - SQRT(A*A + X*X)") == std::pair{0, 0});
    CHECK(found("A + B - SQRT(A*B + B*B)") == std::pair{0, 0});
    CHECK(found("A - B - SQRT(A*A + B*B)") == std::pair{0, 0});
    CHECK(found("SQRT(A*A + B*B) - (A + B)") == std::pair{0, 0});
}

TEST_CASE("written R0 as an R-operation computes the formula's values bit for bit") {
    // Operands of every sign and of very different sizes (the formula rounds to 0 where one is
    // below the other's rounding error), zeros, and NaN from SQRT of a negative.
    test::Compiled c = test::compile_text(
        "ARGUMENT X, Y, Z\n"
        "VARIABLE A = X*X*X - 0.3*Y;\nVARIABLE B = 1E-17*Z + SQRT(Y);\nVARIABLE C = Z - X*Y;\n"
        "VARIABLE W = A + B - SQRT(A*A + B*B);\nVARIABLE V = W + C + SQRT(W*W + C*C);\n"
        "RETURN V + A - SQRT(V^2 + A^2)");
    REQUIRE(c.model);
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
    std::vector<std::array<double, 3>> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 1e-300}, {-1, -1, -1}, {1e-8, 1, 1}};
    for (int i = 0; i < 4000; ++i) points.push_back({coordinate(random), coordinate(random), coordinate(random)});
    const Tape written = compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, false});
    const Tape operations = pruning_tape(c.model->graph, c.model->root);
    int r_operations = 0;
    for (const Instruction& ins : operations.code) r_operations += ins.op == ir::Op::RAnd || ins.op == ir::Op::ROr;
    CHECK(r_operations == 3);
    CHECK(operations.code.size() < written.code.size());
    const std::vector<double> expected = test::run_tape(written, points), got = test::run_tape(operations, points);
    int differing = 0, nans = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        nans += std::isnan(expected[i]);
        differing += std::isnan(expected[i]) ? !std::isnan(got[i])
                                             : std::bit_cast<uint64_t>(expected[i]) != std::bit_cast<uint64_t>(got[i]);
    }
    CHECK(differing == 0);
    CHECK(nans > 100);   // the points with Y < 0 (SQRT(Y))
}

TEST_CASE("a model without written R0 keeps its graph's tape") {
    test::Compiled c = test::compile_text("ARGUMENT X, Y\nRETURN (1 - X*X) & (Y + SQRT(X*X + Y*Y))");
    REQUIRE(c.model);
    const Tape direct = compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, false});
    const Tape pruning = pruning_tape(c.model->graph, c.model->root);
    REQUIRE(pruning.code.size() == direct.code.size());
    for (std::size_t i = 0; i < direct.code.size(); ++i) CHECK(pruning.code[i].op == direct.code[i].op);
}

TEST_CASE("the pawn's written R-operations let intervals decide most of its volume") {
    // examples/pawn.fortu spells every R-operation as a formula. Their intervals were too loose
    // to decide any box: at 64³ all 262,144 points were evaluated one by one, now 71,680 (the
    // 8³ leaves along the surface).
    const std::optional<Model> model = test::load_model_file(std::filesystem::path(FORTU_SOURCE_DIR) / "examples" / "pawn.fortu");
    REQUIRE(model);
    const Grid grid = model_grid(*model, {64, 64, 64});
    SignRenderStats stats;
    const SignVolume volume = sign_render_volume(model->graph, model->root, grid, {}, &stats);
    MESSAGE("leaf points ", stats.leaf_points, " of ", grid.points());
    CHECK(stats.leaf_points * 3 < grid.points());
    const Field full = evaluate_grid(*model, grid, engine_named("voxel"));
    std::size_t differing = 0;
    for (std::size_t i = 0; i < full.values.size(); ++i) differing += volume.sign(i) != ir::k_sign(full.values[i]);
    CHECK(differing == 0);
}
