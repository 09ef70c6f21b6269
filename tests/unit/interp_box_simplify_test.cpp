// tests/unit/interp_box_simplify_test.cpp — the per-box tape pass: intervals over an SSA
// tape, and the exact tape left for a box.
#include "interp_test_support.hpp"

#include "interp/box_simplify.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/stage_print.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <vector>

using namespace fortu;

namespace {

/// The tape of `text` simplified for the box X in [x0, x1], Y in [y0, y1], as text.
std::string simplified(const std::string& text, double x0, double x1, double y0, double y1,
                       bool keep_values = false) {
    auto c = test::compile_text(text);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Tape tape = compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, false});
    std::vector<Interval> ranges;
    evaluate_intervals(tape, {Interval{x0, x1, false}, Interval{y0, y1, false}, Interval{}}, ranges);
    BoxScratch scratch;
    Tape out;
    simplify_for_sign(tape, ranges, scratch, out, keep_values);
    return print_tape(out, c.model->arguments);
}

}  // namespace

TEST_CASE("an SSA tape: one slot per value") {
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN (X * 2 + 1) * (Y - 3)\n");
    REQUIRE(c.model);
    const Tape tape = compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, false});
    CHECK(print_tape(tape, c.model->arguments) ==
          "; 4 operations, 7 slots\n"
          "s1 = arg X\n"
          "s2 = arg Y\n"
          "s3 = mul s1 2\n"
          "s4 = add s3 1\n"
          "s5 = sub s2 3\n"
          "s6 = mul s4 s5\n"
          "return s6\n");
    std::vector<Interval> ranges;
    evaluate_intervals(tape, {Interval{0, 1, false}, Interval{4, 5, false}, Interval{}}, ranges);
    CHECK(ranges[6].lo == 1);
    CHECK(ranges[6].hi == 6);
}

TEST_CASE("a won MIN becomes its operand; a sign-decided R-operand leaves the other") {
    const char* model = "ARGUMENT X, Y\nRETURN MIN(X, X + 10) & (0.5 - Y)\n";
    // X < X + 10 everywhere, and X > 0 on the box: sign(X & W) = sign(W).
    CHECK(simplified(model, 0.1, 0.2, 0, 1) ==
          "; 1 operation, 3 slots\n"
          "s1 = arg Y\n"
          "s2 = sub 0.5 s1\n"
          "return s2\n");
    // X straddles 0: the MIN still goes, the R-operation stays.
    CHECK(simplified(model, -0.1, 0.2, 0, 1) ==
          "; 2 operations, 5 slots\n"
          "s1 = arg X\n"
          "s2 = arg Y\n"
          "s3 = sub 0.5 s2\n"
          "s4 = rand s1 s3 alpha=0\n"
          "return s4\n");
    // Nothing is decided on a box where X + 10 may be the minimum.
    CHECK(simplified(model, -30, 0, 0, 1) ==
          "; 4 operations, 7 slots\n"
          "s1 = arg X\n"
          "s2 = arg Y\n"
          "s3 = add s1 10\n"
          "s4 = min s1 s3\n"
          "s5 = sub 0.5 s2\n"
          "s6 = rand s4 s5 alpha=0\n"
          "return s6\n");
}

TEST_CASE("keeping values: only the exact rules apply, the R-operation stays") {
    const std::string model = "ARGUMENT X, Y\nRETURN MIN(X, X + 10) & (0.5 - Y)\n";
    // On X in [0, 1], Y in [0, 1]: MIN is won by X either way; for the sign 0.5 - Y cannot
    // decide (it changes sign), but the values of the R-operation need both operands.
    CHECK(simplified(model, 0, 1, 0, 1, /*keep_values=*/true) ==
          "; 2 operations, 5 slots\n"
          "s1 = arg X\n"
          "s2 = arg Y\n"
          "s3 = sub 0.5 s2\n"
          "s4 = rand s1 s3 alpha=0\n"
          "return s4\n");
    // Where Y > 0.5 everywhere the sign is decided (-1), the value is not: the tape stays.
    CHECK(simplified(model, 0, 1, 0.6, 1, /*keep_values=*/true) ==
          "; 2 operations, 5 slots\n"
          "s1 = arg X\n"
          "s2 = arg Y\n"
          "s3 = sub 0.5 s2\n"
          "s4 = rand s1 s3 alpha=0\n"
          "return s4\n");
    CHECK(simplified(model, 0, 1, 0.6, 1) == "; 0 operations, 2 slots\ns1 = const -1\nreturn s1\n");
}

TEST_CASE("reallocated slots: compile_tape's allocation, and max-live slots for a deep chain") {
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN (X * 2 + 1) * (Y - 3) + SQRT(X * X + Y * Y)\n");
    REQUIRE(c.model);
    const Tape ssa = compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, false});
    SlotScratch scratch;
    Tape reused;
    reallocate_slots(ssa, reused, scratch);
    CHECK(print_tape(reused, c.model->arguments) ==
          print_tape(compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, true}), c.model->arguments));

    // 1,000 steps of A = A * 0.5 + Y * I: 3,003 SSA slots, 6 when reused; the same values.
    auto deep = test::compile_text("ARGUMENT X, Y;\nA = X;\nFOR I = 1, 1000\n  A = A * 0.5 + Y * I;\nEND FOR\nRETURN A;\n");
    REQUIRE_MESSAGE(deep.model, deep.sink.render_all());
    const Tape deep_ssa = compile_tape(deep.model->graph, TapeSpec{{deep.model->root}, {}, {}, false});
    reallocate_slots(deep_ssa, reused, scratch);
    CHECK(deep_ssa.slot_count == 3003);
    CHECK(reused.slot_count == 6);
    const std::vector<std::array<double, 2>> points{{0.25, -1.5}, {3, 7}, {-2, 0.125}};
    const std::vector<double> expected = test::run_tape(deep_ssa, points);
    const std::vector<double> actual = test::run_tape(reused, points);
    for (std::size_t l = 0; l < points.size(); ++l) CHECK(actual[l] == expected[l]);
}
