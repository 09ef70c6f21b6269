// interp/box_intervals.hpp — the sign renderer's interval pass over one box: every slot's
// range (as evaluate_intervals gives it) and every instruction's choice byte (box_choice.hpp)
// in one walk of the tape.
//
// Why: on prospero.vm the interval pass and the tape shortening were 60% of the sign
// image's instructions. This walk records what the shortening needs while the ranges are in
// registers, and runs the operations prospero-like models are made of (add, sub, mul, neg,
// square, sqrt, abs, min, max) inline on finite operands, with immediates read directly;
// every other operation, and any operand or result that is not finite, goes to the rules
// of interval.hpp (interval_op). On finite operands and results the inline rules are the
// same IEEE operations in the same order as interval.cpp's (sum, difference, product,
// squared, square_root, absolute, minimum, maximum), so the ranges are identical, bit for
// bit (tests/unit/interp_box_intervals_test.cpp compares them on every box of real models).
#pragma once

#include "interp/interval.hpp"
#include "interp/tape.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace fortu {

/// evaluate_intervals(tape, axes, ranges), plus `choices[i]`: instruction_choice of
/// instruction i over the box (box_choice.hpp), the input of simplify_for_sign(choices).
void evaluate_box_intervals(const Tape& tape, const std::array<Interval, 3>& axes, std::vector<Interval>& ranges,
                            std::vector<uint8_t>& choices);

}  // namespace fortu
