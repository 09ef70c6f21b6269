// tests/unit/interp_lower_test.cpp — semantics of lowering: precedence facts, sections,
// names, hash-consing and constant folding, and the exact text of semantic diagnostics.
#include "interp_test_support.hpp"

#include "interp/classic_cost.hpp"
#include "interp/classic_engine.hpp"
#include "interp/ir_print.hpp"

#include <doctest/doctest.h>

using namespace fortu;
using fortu::test::compile_text;
using fortu::test::value_at;

TEST_CASE("precedence facts of spec §3 hold in both engines") {
    for (const Engine& engine : exact_engines()) {
        CAPTURE(engine.name());
        CHECK(value_at("ARGUMENT X; RETURN -2^2;", 0, 0, 0, engine) == -4);
        CHECK(value_at("ARGUMENT X; RETURN 2^3^2;", 0, 0, 0, engine) == 512);
        CHECK(value_at("ARGUMENT X; RETURN 2^-2;", 0, 0, 0, engine) == 0.25);
        CHECK(value_at("ARGUMENT X; RETURN 0&3;", 0, 0, 0, engine) == 0);
        CHECK(value_at("ARGUMENT X; RETURN 2**3;", 0, 0, 0, engine) == 8);
        CHECK(value_at("ARGUMENT X,Y; RETURN X&Y;", 3, 4, 0, engine) == 3 + 4 - 5);
        CHECK(value_at("ARGUMENT X,Y; RETURN X|Y;", 3, 4, 0, engine) == 3 + 4 + 5);
        CHECK(value_at("ARGUMENT X,Y; RETURN !X;", 3, 4, 0, engine) == -3);
        CHECK(value_at("ARGUMENT X,Y; RETURN 1 | 2 & 3;", 0, 0, 0, engine) ==
              doctest::Approx(1 + (5 - std::sqrt(13.0)) + std::sqrt(1 + std::pow(5 - std::sqrt(13.0), 2))));
        CHECK(value_at("ARGUMENT X,Y; RSYSTEM MINMAX; RETURN X&Y;", 3, 4, 0, engine) == 3);
        CHECK(value_at("ARGUMENT X,Y; RSYSTEM MINMAX; RETURN X|Y;", 3, 4, 0, engine) == 4);
        CHECK(value_at("ARGUMENT X,Y; RSYSTEM ALPHA=0.5; RETURN X&Y;", 3, 4, 0, engine) ==
              doctest::Approx((7 - std::sqrt(9 + 16 - 12.0)) / 1.5));
        CHECK(value_at("ARGUMENT X,Y; RETURN RAND(X, Y) - (X & Y);", 3, 4, 0, engine) == 0);
    }
}

TEST_CASE("the 3x3 grid of spec §2: RECTANGLE(-1,-1,1,1) RECTBMP(3,3), y+x") {
    auto c = compile_text("RECTANGLE(-1,-1,1,1)\nRECTBMP(3,3)\nARGUMENT x, y\nRETURN y+x\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    REQUIRE(c.model->raster);
    Grid g;
    g.dims = 2;
    g.x = {c.model->ranges[0]->min, c.model->ranges[0]->max, (*c.model->raster)[0]};
    g.y = {c.model->ranges[1]->min, c.model->ranges[1]->max, (*c.model->raster)[1]};
    for (const Engine& engine : exact_engines()) {
        Field f = evaluate_grid(*c.model, g, engine);
        CHECK(f.values == std::vector<double>{0, 1, 2, -1, 0, 1, -2, -1, 0});
    }
}

TEST_CASE("re-definition: each use sees the latest definition before it") {
    CHECK(value_at("ARGUMENT X; CONSTANT A = 1; VARIABLE B = A + X; CONSTANT A = 10; RETURN A + B;", 2) == 13);
    CHECK(value_at("ARGUMENT X; CONSTANT A = 1; VARIABLE A = A + X; RETURN A;", 2) == 3);
}

TEST_CASE("a FUNCTION body sees the names in force where it is written, not where it is called") {
    // spec §2: each use sees the latest definition before it; a function body is a use at its
    // own place in the text (lexical binding).
    const std::string text = "ARGUMENT X, Y;\nCONSTANT K = 1;\nFUNCTION F(A)\n  RETURN K*A;\nEND\n"
                             "VARIABLE BEFORE = F(X);\nCONSTANT K = 100;\nVARIABLE AFTER = F(X);\n"
                             "RETURN BEFORE + 1000*AFTER + K;\n";
    for (const Engine& engine : exact_engines()) CHECK(value_at(text, 2, 0, 0, engine) == 2 + 1000 * 2 + 100);
    // the same through a second function, and for a variable re-defined between calls
    CHECK(value_at("ARGUMENT X, Y; VARIABLE W = X; FUNCTION G(A) RETURN A + W; END; FUNCTION H(A) RETURN G(A) * 10; END;"
                   "VARIABLE W = 1000; RETURN H(1) + W;", 2) == 1030);
    // a name defined only after the function is unknown in its body
    auto c = compile_text("ARGUMENT X, Y;\nFUNCTION F(A)\n  RETURN L*A;\nEND\nCONSTANT L = 2;\nRETURN F(X);\n");
    CHECK_FALSE(c.model);
    CHECK(c.sink.render_all() == "test.fortu:3:10: error: unknown name 'L'\n  RETURN L*A;\n         ^\n");
}

TEST_CASE("built-in functions and PI, case-insensitive; user PI shadows the built-in") {
    CHECK(value_at("ARGUMENT X; RETURN sqrt(16) + Abs(-2) + MIN(3, 1, 2) + max(1, 5);") == 4 + 2 + 1 + 5);
    CHECK(value_at("ARGUMENT X; RETURN pi;") == M_PI);
    CHECK(value_at("ARGUMENT X; CONSTANT PI=3; RETURN PI;") == 3);
    CHECK(value_at("ARGUMENT X; RETURN ATAN2(1, 1) - ATAN(1, 1);") == 0);
    CHECK(value_at("ARGUMENT X; RETURN MOD(7, 3) + SIGN(-2) + FLOOR(1.5) + CEIL(1.5) + HYPOT(3, 4);") == 1 - 1 + 1 + 2 + 5);
    CHECK(value_at("ARGUMENT X; RETURN LOG(EXP(2)) + LN(1) + LOG10(100) + LOG2(8);") == doctest::Approx(2 + 0 + 2 + 3));
}

TEST_CASE("built-in names come from ops.def: aliases, overloads by argument count, arity messages") {
    CHECK(value_at("ARGUMENT X; RETURN ARCTAN(1, 2) - ATAN2(1, 2);") == 0);
    CHECK(value_at("ARGUMENT X; RETURN ARCTAN(0.5) - ATAN(0.5) + ARCSIN(0.5) - ASIN(0.5) + ARCCOS(0.5) - ACOS(0.5);") == 0);
    CHECK(value_at("ARGUMENT X; RETURN RNOT(X) + ror(X, 1, 2) - ROR(ROR(X, 1), 2);", 3) == -3);
    CHECK(value_at("ARGUMENT X; CONSTANT A = [4, 5, 6]; RETURN size(A);") == 3);
    auto errors = [](const std::string& text) {
        auto c = compile_text(text);
        CHECK_FALSE(c.model);
        return c.sink.render_all();
    };
    CHECK(errors("ARGUMENT X;\nRETURN Atan(X, X, X);\n") ==
          "test.fortu:2:8: error: ATAN takes 1 or 2 arguments, got 3\n"
          "RETURN Atan(X, X, X);\n"
          "       ^~~~~~~~~~~~~\n");
    CHECK(errors("ARGUMENT X;\nRETURN MAX(X);\n") ==
          "test.fortu:2:8: error: MAX takes at least 2 arguments, got 1\n"
          "RETURN MAX(X);\n"
          "       ^~~~~~\n");
    CHECK(errors("ARGUMENT X;\nRETURN SELECT(X, X);\n") ==
          "test.fortu:2:8: error: SELECT takes 3 arguments, got 2\n"
          "RETURN SELECT(X, X);\n"
          "       ^~~~~~~~~~~~\n");
    CHECK(errors("ARGUMENT X;\nRETURN FROB(X);\n") ==
          "test.fortu:2:8: error: unknown function 'FROB'\n"
          "RETURN FROB(X);\n"
          "       ^~~~\n");
}

TEST_CASE("hash-consing shares equal sub-expressions and folds constants") {
    auto c = compile_text("ARGUMENT X, Y;\nCONSTANT C = 1./2.*4;\nVARIABLE W = (X-1.3)*(X-1.3) + (X-1.3)*(X-1.3) + C;\nRETURN W;\n");
    REQUIRE(c.model);
    const IrStats s = ir_stats(*c.model);
    // X, 1.3, X-1.3, (X-1.3)^2, sum, 2, sum+2: seven nodes
    CHECK(s.nodes == 7);
    CHECK(s.operations == 4);
    CHECK(s.shared == 2);   // used twice by the product, the product twice by the sum
    // classic walks the tree as written, every node of it counting 1: is 3 nodes,
    // the product 1 + 2*3, the sum of two products 1 + 2*7, plus the constant: 1 + 15 + 1
    CHECK(classic_operations_per_point(c.model->graph, c.model->root) == 17);
}

TEST_CASE("classic cost doubles with each nested R0 operation") {
    // W1 = X & Y; Wk = W(k-1) & X: the left operand is referenced twice by the formula
    // (6 operations of its own, leaves 1 each): cost(W1) = 10, cost(Wk) = 2 cost(Wk-1) + 8.
    std::string text = "ARGUMENT X, Y;\nVARIABLE W = X & Y;\n";
    double previous = 0;
    for (int depth = 1; depth <= 12; ++depth) {
        auto c = compile_text(text + "RETURN W;\n");
        REQUIRE(c.model);
        const double cost = classic_operations_per_point(c.model->graph, c.model->root);
        CHECK(cost == 18 * std::pow(2.0, depth - 1) - 8);
        if (depth > 1) CHECK(cost == 2 * previous + 8);
        previous = cost;
        CHECK(ir_stats(*c.model).operations == static_cast<std::size_t>(depth));
        text += "VARIABLE W = W & X;\n";
    }
}

TEST_CASE("the classic engine saves nothing: it evaluates every node of the expanded tree") {
    // W1 = X & Y is 5 nodes expanded (the R-node, X and Y twice each); Wk = W(k-1) & X is
    // 1 + 2 cost(W(k-1)) + 2: 8 * 2^(k-1) - 3. A memoising (or compiler-merged) walk would
    // evaluate 2k + 1 nodes.
    std::string text = "ARGUMENT X, Y;\nVARIABLE W = X & Y;\n";
    for (int depth = 1; depth <= 16; ++depth) {
        auto c = compile_text(text + "RETURN W;\n");
        REQUIRE(c.model);
        CHECK(classic_node_evaluations(c.model->graph, c.model->root, {0.3, 0.4, 0}) ==
              8 * (std::uint64_t{1} << (depth - 1)) - 3);
        text += "VARIABLE W = W & X;\n";
    }
}

TEST_CASE("classic cost counts the R-formula's operand references") {
    auto c = compile_text("ARGUMENT X, Y; RETURN X & Y;");
    REQUIRE(c.model);
    const ir::Node& n = c.model->graph.node(c.model->root);
    CHECK(classic_operand_uses(n, 0) == 2);
    CHECK(classic_operand_uses(n, 1) == 2);
    auto r1 = compile_text("ARGUMENT X, Y; RSYSTEM MINMAX; RETURN X & Y;");
    CHECK(classic_operand_uses(r1.model->graph.node(r1.model->root), 0) == 1);
    auto ra = compile_text("ARGUMENT X, Y; RSYSTEM ALPHA = 0.5; RETURN X & Y;");
    CHECK(classic_operand_uses(ra.model->graph.node(ra.model->root), 0) == 3);
}

TEST_CASE("the command line's R-system wins over RSYSTEM in the script") {
    CompileOptions options;
    options.rsystem = RSystem{1.0};
    auto c = compile_text("ARGUMENT X, Y; RSYSTEM R0; RETURN X & Y;", options);
    REQUIRE(c.model);
    CHECK(evaluate_point(*c.model, {3, 4, 0}, engine_named("voxel")).value == 3);
    CHECK(parse_rsystem("alpha=0.5")->alpha == 0.5);
    CHECK(parse_rsystem("MINMAX")->alpha == 1.0);
    CHECK_FALSE(parse_rsystem("alpha=-1"));
    CHECK_FALSE(parse_rsystem("alpha=1.5"));
    CHECK_FALSE(parse_rsystem("r2"));
}

TEST_CASE("argument ranges, RECTANGLE and RECTBMP set the domain") {
    auto c = compile_text("ARGUMENT X(5), Y(0, 10), Z;\nRETURN X;\n");
    REQUIRE(c.model);
    CHECK(c.model->ranges[0]->min == -5);
    CHECK(c.model->ranges[0]->max == 5);
    CHECK(c.model->ranges[1]->min == 0);
    CHECK(c.model->ranges[1]->max == 10);
    CHECK_FALSE(c.model->ranges[2]);
    CHECK(c.model->dims() == 3);
}

TEST_CASE("exact gradients through dual numbers agree between engines") {
    const char* text = "ARGUMENT X, Y;\nVARIABLE A = 1 - X^2 - Y^2;\nVARIABLE B = X - 0.2*Y;\nRETURN (A & B) | SIN(X*Y);\n";
    auto c = compile_text(text);
    REQUIRE(c.model);
    PointValue v = evaluate_point(*c.model, {0.3, -0.4, 0}, engine_named("voxel"));
    PointValue k = evaluate_point(*c.model, {0.3, -0.4, 0}, engine_named("classic"));
    CHECK(v.value == k.value);
    CHECK(v.gradient == k.gradient);
    const double h = 1e-6;
    for (int axis = 0; axis < 2; ++axis) {
        std::array<double, 3> p{0.3, -0.4, 0}, q = p;
        p[axis] += h;
        q[axis] -= h;
        const double fd = (evaluate_point(*c.model, p, engine_named("voxel")).value -
                           evaluate_point(*c.model, q, engine_named("voxel")).value) / (2 * h);
        CHECK(v.gradient[axis] == doctest::Approx(fd).epsilon(1e-6));
    }
}

TEST_CASE("invalid points are values, not errors") {
    auto c = compile_text("ARGUMENT X, Y; RETURN 1/X;");
    REQUIRE(c.model);
    Grid g;
    g.x = {-1, 1, 3};
    g.y = {-1, 1, 3};
    for (const Engine& engine : exact_engines()) {
        Field f = evaluate_grid(*c.model, g, engine);
        CHECK(f.invalid_count() == 3);
    }
}

TEST_CASE("user functions, arrays and FOR loops lower to the same IR") {
    const char* text =
        "ARGUMENT X, Y;\n"
        "FUNCTION SEG(X, Y, X1, Y1, X2, Y2)\n"
        "  RETURN SQRT((X-X1)^2+(Y-Y1)^2) + SQRT((X-X2)^2+(Y-Y2)^2) - SQRT((X2-X1)^2+(Y2-Y1)^2);\n"
        "END\n"
        "CONSTANT PX = [0, 1, 1], PY = [0, 0, 1], N = SIZE(PX);\n"
        "VARIABLE W = SEG(X, Y, PX(N), PY(N), PX(1), PY(1));\n"
        "FOR I = 1, N - 1\n"
        "  W = W & SEG(X, Y, PX(I), PY(I), PX(I+1), PY(I+1));\n"
        "END FOR\n"
        "RETURN W;\n";
    auto c = compile_text(text);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    for (const Engine& engine : exact_engines()) {
        CHECK(evaluate_point(*c.model, {0.5, 0, 0}, engine).value == doctest::Approx(0).epsilon(1e-12));
        CHECK(evaluate_point(*c.model, {0.5, 0.5, 0}, engine).value == doctest::Approx(0).epsilon(1e-12));
        CHECK(evaluate_point(*c.model, {0.7, 0.2, 0}, engine).value > 0);
    }
}
