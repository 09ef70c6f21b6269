// tests/unit/interp_session_test.cpp — the REPL's incremental session: re-definitions in
// place, diagnostics on the typed line, the saved script, and which evaluations are reused.
#include "interp/session.hpp"

#include "interp_test_support.hpp"

#include <doctest/doctest.h>

using namespace fortu;
using Kind = SubmitResult::Kind;

namespace {

double value_at_origin(const Session& s) { return evaluate_point(s.model(), {0.0, 0.0, 0.0}, EngineKind::Voxel).value; }

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
    CHECK(evaluate_point(*r.model, {1.0, 0.0, 0.0}, EngineKind::Classic).value == 3);
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
    const Field first = s.evaluate(grid, EngineKind::Voxel, {}, report);
    CHECK_FALSE(report.reused);
    CHECK(report.unchanged_nodes == 0);
    const std::size_t nodes = report.nodes;
    // An unrelated definition does not change the model's DAG: nothing is evaluated.
    s.submit("CONSTANT UNUSED = 7", "<input>");
    CHECK(s.evaluate(grid, EngineKind::Classic, {}, report).values == first.values);
    CHECK(report.reused);
    // A new radius changes the constant and the two subtractions above it; X², Y², X and Y
    // are unchanged.
    s.submit("R = 0.75", "<input>");
    const Field second = s.evaluate(grid, EngineKind::Voxel, {}, report);
    CHECK_FALSE(report.reused);
    CHECK(report.nodes == nodes);
    CHECK(report.unchanged_nodes == nodes - 3);
    CHECK(second.values[12] == 0.75);
    // Changed back: the earlier values come from the cache.
    s.submit("R = 0.5", "<input>");
    CHECK(s.evaluate(grid, EngineKind::Voxel, {}, report).values == first.values);
    CHECK(report.reused);
}

TEST_CASE("structural hashes are equal for equal expressions in different graphs") {
    auto a = test::compile_text("ARGUMENT X, Y\nRETURN SIN(X) + Y * 2");
    auto b = test::compile_text("ARGUMENT X, Y\nVARIABLE Q = 3\nRETURN Y * 2 + SIN(X)");
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN SIN(Y) + X * 2");
    const auto hash = [](const test::Compiled& m) { return structural_hashes(m.model->graph, m.model->root)[m.model->root]; };
    CHECK(hash(a) == hash(b));
    CHECK(hash(a) != hash(c));
}
