// tests/unit/interp_session_test.cpp — the REPL's incremental session: re-definitions in
// place, diagnostics on the typed line, the saved script, and which evaluations are reused.
#include "interp/session.hpp"

#include "interp_test_support.hpp"

#include <doctest/doctest.h>

using namespace fortu;
using Kind = SubmitResult::Kind;

namespace {

double value_at_origin(const Session& s) { return evaluate_point(s.model(), {0.0, 0.0, 0.0}, engine_named("voxel")).value; }

}  // namespace

TEST_CASE("re-defining a constant replaces it in place and later definitions follow") {
    Session s({});
    CHECK(s.submit("ARGUMENT X, Y", "<input>").kind == Kind::Statements);
    CHECK(s.submit("CONSTANT R = 0.5", "<input>").kind == Kind::Statements);
    CHECK(s.submit("D = R - SQRT(X^2 + Y^2)", "<input>").kind == Kind::Statements);
    CHECK_FALSE(s.has_model());
    CHECK(s.submit("RETURN D", "<input>").changes == std::vector<std::string>{"model set"});
    CHECK(value_at_origin(s) == 0.5);
    const SubmitResult r = s.submit("R = 0.25", "<input>");
    CHECK(r.kind == Kind::Statements);
    CHECK(r.changes == std::vector<std::string>{"replaced R"});
    CHECK(value_at_origin(s) == 0.25);
    // A definition that uses its own name refines it, as in a file.
    CHECK(s.submit("D = D & (X + 0.1)", "<input>").changes == std::vector<std::string>{"refined D"});
    CHECK(s.script() ==
          "// A fortu repl session, saved with :save.\n"
          "RECTBMP(256, 256)\n"
          "ARGUMENT X(-1, 1), Y(-1, 1)\n"
          "CONSTANT R = 0.25\n"
          "VARIABLE D = R - SQRT(X^2 + Y^2)\n"
          "VARIABLE D = D & (X + 0.1)\n"
          "RETURN D\n");
}

TEST_CASE("rejected input leaves the session unchanged; diagnostics point into the typed line") {
    Session s({});
    s.submit("ARGUMENT X, Y; CONSTANT R = 0.5; RETURN R - X", "<input>");
    SubmitResult r = s.submit("VARIABLE E = R + Q", "<input>");
    CHECK(r.kind == Kind::Error);
    CHECK(r.diagnostics == "<input>:1:18: error: unknown name 'Q'\nVARIABLE E = R + Q\n                 ^\n");
    r = s.submit("R = ", "<input>");
    CHECK(r.kind == Kind::Error);
    CHECK(r.diagnostics.rfind("<input>:1:", 0) == 0);
    CHECK(value_at_origin(s) == 0.5);
    // A constant that now needs an argument turns into a VARIABLE, and the model follows it.
    CHECK(s.submit("R = Y + 2", "<input>").kind == Kind::Statements);
    CHECK(value_at_origin(s) == 2);
}

TEST_CASE("a bare expression is evaluated against the session's definitions") {
    Session s({});
    s.submit("ARGUMENT X, Y\nCONSTANT R = 0.5\nRETURN R", "<input>");
    SubmitResult r = s.submit("R * 4 + X", "<input>");
    REQUIRE(r.kind == Kind::Expression);
    CHECK(evaluate_point(*r.model, {1.0, 0.0, 0.0}, engine_named("classic")).value == 3);
    r = s.submit("R * W", "<input>");
    CHECK(r.kind == Kind::Error);
    CHECK(r.diagnostics == "<input>:1:5: error: unknown name 'W'\nR * W\n    ^\n");
    CHECK(s.submit("  // only a comment", "<input>").kind == Kind::Empty);
}

TEST_CASE("grid values are reused when the model's DAG and the grid are unchanged") {
    Session s({});
    s.submit("ARGUMENT X, Y\nCONSTANT R = 0.5\nVARIABLE D = R - X*X - Y*Y\nRETURN D", "<input>");
    s.set_size({5});
    const Grid grid = s.grid();
    EvalReport report;
    const Field first = s.evaluate(grid, engine_named("voxel"), {}, report);
    CHECK_FALSE(report.reused);
    CHECK(report.computed_operations == report.operations);
    // An unrelated definition does not change the model's DAG: nothing is evaluated.
    s.submit("CONSTANT UNUSED = 7", "<input>");
    CHECK(s.evaluate(grid, engine_named("classic"), {}, report).values == first.values);
    CHECK(report.reused);
    CHECK(report.computed_operations == 0);
    s.submit("R = 0.75", "<input>");
    const Field second = s.evaluate(grid, engine_named("voxel"), {}, report);
    CHECK_FALSE(report.reused);
    CHECK(second.values[12] == 0.75);
    // Changed back: the earlier values are still kept.
    s.submit("R = 0.5", "<input>");
    CHECK(s.evaluate(grid, engine_named("voxel"), {}, report).values == first.values);
    CHECK(report.reused);
    // Another grid is another set of values.
    s.set_size({6});
    s.evaluate(s.grid(), engine_named("voxel"), {}, report);
    CHECK_FALSE(report.reused);
}

TEST_CASE("after a change only what depends on it is computed; the rest is read from kept values") {
    Session s({});
    s.submit("ARGUMENT X(-2, 2), Y(-2, 2)\n"
             "VARIABLE D = SQRT(X*X + Y*Y)\n"
             "VARIABLE W = SIN(X * 3) * COS(Y * 5) + 0.1 * SIN(X * Y)\n"
             "CONSTANT R = 1\n"
             "VARIABLE S = (R - D) & W\n"
             "RETURN S", "<input>");
    for (int size : {80, 20}) {   // row tiles with hoisting, and flat tiles
        CAPTURE(size);
        s.set_size({size});
        s.submit("R = 1", "<input>");
        const Grid grid = s.grid();
        EvalReport report;
        s.evaluate(grid, engine_named("voxel"), {}, report);
        CHECK(report.computed_operations == report.operations);
        CHECK(report.reused_definitions.empty());
        CHECK(report.kept_definitions == 2);   // D and W (S is the model: kept as such)

        // A new radius: D and W are read, only R - D and the & are computed.
        s.submit("R = 0.6", "<input>");
        const Field incremental = s.evaluate(grid, engine_named("voxel"), {}, report);
        CHECK(report.computed_operations == 2);
        CHECK(report.reused_definitions == std::vector<std::string>{"D", "W"});
        CHECK(report.kept_definitions == 0);
        CHECK(incremental.values == evaluate_grid(s.model(), grid, engine_named("voxel")).values);
        CHECK(incremental.values == evaluate_grid(s.model(), grid, engine_named("classic")).values);

        // A new D: W is still read; D is computed again, and kept.
        s.submit("D = SQRT(X*X + Y*Y) - 0.2 * COS(3 * X)", "<input>");
        const Field redefined = s.evaluate(grid, engine_named("voxel"), {}, report);
        CHECK(report.reused_definitions == std::vector<std::string>{"W"});
        CHECK(report.kept_definitions == 1);
        CHECK(report.computed_operations < report.operations);
        CHECK(redefined.values == evaluate_grid(s.model(), grid, engine_named("classic")).values);
        s.submit("D = SQRT(X*X + Y*Y)", "<input>");
    }
    // The classic engine saves nothing: it computes everything, reads nothing.
    s.submit("R = 0.7", "<input>");
    EvalReport report;
    s.evaluate(s.grid(), engine_named("classic"), {}, report);
    CHECK(report.computed_operations == report.operations);
    CHECK(report.reused_definitions.empty());
}

TEST_CASE("structural hashes are equal for equal expressions in different graphs") {
    auto a = test::compile_text("ARGUMENT X, Y\nRETURN SIN(X) + Y * 2");
    auto b = test::compile_text("ARGUMENT X, Y\nVARIABLE Q = 3\nRETURN Y * 2 + SIN(X)");
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN SIN(Y) + X * 2");
    const auto hash = [](const test::Compiled& m) { return structural_hashes(m.model->graph, m.model->root)[m.model->root]; };
    CHECK(hash(a) == hash(b));
    CHECK(hash(a) != hash(c));
}

TEST_CASE("a FOR loop's redefinitions are one kept cell, not one per step") {
    Session s({});
    s.submit("ARGUMENT X, Y\nVARIABLE D = 0\nFOR I = 1, 200\nD = D | (0.01 - SQRT((X - I/100)^2 + Y^2))\nEND FOR\n"
             "VARIABLE E = D & (0.5 - ABS(Y))\nRETURN E", "<input>");
    s.set_size({70});
    EvalReport report;
    s.evaluate(s.grid(), engine_named("voxel"), {}, report);
    CHECK(report.kept_definitions == 1);   // the last D
    s.submit("E = D & (0.4 - ABS(Y))", "<input>");
    s.evaluate(s.grid(), engine_named("voxel"), {}, report);
    CHECK(report.reused_definitions == std::vector<std::string>{"D"});
    CHECK(report.computed_operations == 3);   // ABS(Y), 0.4 - ABS(Y) and the &: nothing of D
}

TEST_CASE("a kept definition under another kept one is not read, nor reported") {
    Session s({});
    s.submit("ARGUMENT X, Y\nVARIABLE D = SQRT(X*X + Y*Y)\nVARIABLE W = SIN(D * 7)\nCONSTANT R = 1\nRETURN R * W",
             "<input>");
    s.set_size({70});
    EvalReport report;
    s.evaluate(s.grid(), engine_named("voxel"), {}, report);
    CHECK(report.kept_definitions == 2);
    s.submit("R = 2", "<input>");
    const Field f = s.evaluate(s.grid(), engine_named("voxel"), {}, report);
    CHECK(report.reused_definitions == std::vector<std::string>{"W"});
    CHECK(report.computed_operations == 1);
    CHECK(f.values == evaluate_grid(s.model(), s.grid(), engine_named("classic")).values);
}

TEST_CASE("a FUNCTION sees the definitions written before it; re-defining one in place changes what it sees") {
    Session s({});
    s.submit("ARGUMENT X, Y\nCONSTANT K = 1\nFUNCTION F(A)\n  RETURN K*A\nEND\nRETURN F(X + 3)", "<input>");
    REQUIRE(s.has_model());
    CHECK(value_at_origin(s) == 3);
    // K is re-defined in place, before F: F sees the new value (the saved script says so too)
    CHECK(s.submit("CONSTANT K = 100", "<input>").changes == std::vector<std::string>{"replaced K"});
    CHECK(value_at_origin(s) == 300);
    // a new name after F is not seen by F's body
    CHECK(s.submit("CONSTANT L = 7\nRETURN F(X + 3) + L", "<input>").kind == Kind::Statements);
    CHECK(value_at_origin(s) == 307);
}

TEST_CASE("a FUNCTION re-defined with a body using later names moves after them") {
    Session s({});
    s.submit("ARGUMENT X, Y\nFUNCTION F(A)\n  RETURN A\nEND\nCONSTANT K = 2\nRETURN F(X + 3)", "<input>");
    REQUIRE(s.has_model());
    CHECK(value_at_origin(s) == 3);
    const SubmitResult r = s.submit("FUNCTION F(A)\n  RETURN K*A\nEND", "<input>");
    CHECK(r.kind == Kind::Statements);
    CHECK(r.changes == std::vector<std::string>{"replaced F"});
    CHECK(value_at_origin(s) == 6);
}
