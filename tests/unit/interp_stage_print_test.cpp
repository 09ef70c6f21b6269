// tests/unit/interp_stage_print_test.cpp — `fortu ir --stage`: the exact text of the tape
// and of the hoisted split on a small model.
#include "interp_test_support.hpp"

#include "interp/ir_print.hpp"
#include "interp/stage_print.hpp"

#include <doctest/doctest.h>

using namespace fortu;

namespace {

const char* const kModel = "ARGUMENT X, Y\nRETURN SIN(X * 2) * COS(Y * 3) + SQRT(Y * Y + 1) & (0.5 - X)\n";

}  // namespace

TEST_CASE("the stages by name") {
    CHECK(parse_ir_stage("lower") == IrStage::Lower);
    CHECK(parse_ir_stage("tape") == IrStage::Tape);
    CHECK(parse_ir_stage("hoist") == IrStage::Hoist);
    CHECK_FALSE(parse_ir_stage("Tape"));
    CHECK_FALSE(parse_ir_stage(""));
}

TEST_CASE("stage lower is the lowered DAG, as fortu ir prints it") {
    auto c = test::compile_text(kModel);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(print_stage(*c.model, "m.fortu", IrStage::Lower) == print_ir(*c.model, "m.fortu"));
}

TEST_CASE("stage tape: slots reused after a value's last use, constants as immediates") {
    auto c = test::compile_text(kModel);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(print_stage(*c.model, "m.fortu", IrStage::Tape) ==
          "; m.fortu\n"
          "; tape (no hoisting)\n"
          "; 11 operations, 6 slots\n"
          "s1 = arg X\n"
          "s2 = arg Y\n"
          "s3 = mul s1 2\n"
          "s4 = sin s3\n"
          "s3 = mul s2 3\n"
          "s5 = cos s3\n"
          "s3 = mul s4 s5\n"
          "s5 = mul s2 s2\n"
          "s4 = add s5 1\n"
          "s5 = sqrt s4\n"
          "s4 = add s3 s5\n"
          "s5 = sub 0.5 s1\n"
          "s3 = rand s4 s5 alpha=0\n"
          "return s3\n");
}

TEST_CASE("stage hoist: X-only values per column, values without X per row, the rest per point") {
    auto c = test::compile_text(kModel);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(print_stage(*c.model, "m.fortu", IrStage::Hoist) ==
          "; m.fortu\n"
          "; hoisted on grids of 64+ columns: 3 operations per column, 5 per row, 3 per point\n"
          "; once per grid column (X only): the column values column 0..\n"
          "; 3 operations, 4 slots\n"
          "s1 = arg X\n"
          "s2 = mul s1 2\n"
          "s3 = sin s2\n"
          "s2 = sub 0.5 s1\n"
          "column 0 = s3\n"
          "column 1 = s2\n"
          "; once per grid row (no X): the row values row 0..\n"
          "; 5 operations, 5 slots\n"
          "s1 = arg Y\n"
          "s2 = mul s1 3\n"
          "s3 = cos s2\n"
          "s2 = mul s1 s1\n"
          "s4 = add s2 1\n"
          "s2 = sqrt s4\n"
          "row 0 = s3\n"
          "row 1 = s2\n"
          "; at every point: column values as lane arrays, row values as immediates\n"
          "; 3 operations, 5 slots\n"
          "s1 = column 0\n"
          "s2 = column 1\n"
          "s3 = mul s1 row[0]\n"
          "s4 = add s3 row[1]\n"
          "s3 = rand s4 s2 alpha=0\n"
          "return s3\n");
}

TEST_CASE("stage tape counts one operation in the singular") {
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN SQRT(X)\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    CHECK(print_stage(*c.model, "m.fortu", IrStage::Tape) ==
          "; m.fortu\n"
          "; tape (no hoisting)\n"
          "; 1 operation, 3 slots\n"
          "s1 = arg X\n"
          "s2 = sqrt s1\n"
          "return s2\n");
}
