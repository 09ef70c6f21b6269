// interp/box_choice.hpp — what a box's ranges decide for one instruction, in one byte: which
// operand a min/max/select/R-operation equals (for its value, or only for its sign), and
// whether its sign is decided. The per-box tape shortening (box_simplify.hpp) acts on it.
//
// Why a byte: the shortening's backward pass used to look at three 24-byte ranges per
// instruction a second time after the interval pass; recorded while the interval pass
// (box_intervals.hpp) has those ranges in registers, the choice costs a few compares, and
// the shortening reads one byte (Fidget's and prospero_vm's "choices").
#pragma once

#include "interp/interval.hpp"
#include "interp/tape.hpp"

#include <array>
#include <cstdint>

namespace fortu {
namespace box_choice {

inline constexpr uint8_t kNone = 3;             ///< in either 2-bit field: no operand wins
inline constexpr uint8_t kValueShift = 0;       ///< bits 0-1: the operand equal to the value
inline constexpr uint8_t kSignShift = 2;        ///< bits 2-3: an operand with the value's sign
inline constexpr uint8_t kPositive = 1u << 4;   ///< the value is > 0 over the box (a number)
inline constexpr uint8_t kNegative = 1u << 5;   ///< the value is < 0 over the box (a number)
inline constexpr uint8_t kUndecided = (kNone << kValueShift) | (kNone << kSignShift);

inline int value_operand(uint8_t choice) { return (choice >> kValueShift) & 3; }
inline int sign_operand(uint8_t choice) { return (choice >> kSignShift) & 3; }

/// The operand (0, 1, 2) equal to the instruction over the whole box, for its value
/// (sign_only false) or for its sign; kNone when none is. a, b, c: the operands' ranges.
inline int chosen_operand(const Instruction& ins, const Interval& a, const Interval& b, const Interval& c,
                          bool sign_only) {
    (void)c;
    if (ins.op == ir::Op::Select) {
        if (a.positive()) return 1;
        if (a.hi <= 0 && !a.maybe_nan) return 2;
        return kNone;
    }
    const bool is_min = ins.op == ir::Op::Min || (ins.op == ir::Op::RAnd && ins.imm == 1.0);
    const bool is_max = ins.op == ir::Op::Max || (ins.op == ir::Op::ROr && ins.imm == 1.0);
    const bool conj = is_min || ins.op == ir::Op::RAnd;
    const bool disj = is_max || ins.op == ir::Op::ROr;
    if (!conj && !disj) return kNone;
    const bool numbers = !a.maybe_nan && !b.maybe_nan;
    // Exact: one operand is the minimum (maximum) at every point.
    if (is_min && numbers) {
        if (a.hi < b.lo) return 0;
        if (b.hi < a.lo) return 1;
    }
    if (is_max && numbers) {
        if (a.lo > b.hi) return 0;
        if (b.lo > a.hi) return 1;
    }
    if (!sign_only) return kNone;
    // An R-formula with α ≠ 1 gives ∞ − ∞ = NaN from an infinite operand: finite ranges only.
    if (!is_min && !is_max && !(a.bounded() && b.bounded())) return kNone;
    // sign(a & b) = sign(min(a, b)); sign(a | b) = sign(max(a, b)).
    if (conj) {
        if (a.positive()) return 1;
        if (b.positive()) return 0;
        if (a.negative() && !b.maybe_nan) return 0;
        if (b.negative() && !a.maybe_nan) return 1;
    } else {
        if (a.negative()) return 1;
        if (b.negative()) return 0;
        if (a.positive() && !b.maybe_nan) return 0;
        if (b.positive() && !a.maybe_nan) return 1;
    }
    return kNone;
}

/// The choice of a min or a max from six predicates, bit k of `predicates`, the first true
/// one winning as in chosen_operand: bit 0 operand 0 is the value, bit 1 operand 1 is; then
/// for the sign only, bit 2 operand 1, bit 3 operand 0, bit 4 operand 0, bit 5 operand 1.
/// For min(a, b): a.hi < b.lo, b.hi < a.lo (both numbers), a > 0, b > 0, a < 0 (b a number),
/// b < 0 (a a number); for max the mirror: a.lo > b.hi, b.lo > a.hi, a < 0, b < 0, a > 0,
/// b > 0. A table, not branches: the predicates are random from one instruction to the next.
inline constexpr std::array<uint8_t, 64> kMinMaxChoices = [] {
    std::array<uint8_t, 64> table{};
    constexpr int kSignOperand[6] = {0, 1, 1, 0, 0, 1};
    for (int bits = 0; bits < 64; ++bits) {
        int value = kNone, sign = kNone;
        if (bits & 1) value = 0;
        else if (bits & 2) value = 1;
        for (int k = 0; k < 6 && sign == kNone; ++k)
            if (bits & (1 << k)) sign = kSignOperand[k];
        table[bits] = static_cast<uint8_t>(value << kValueShift | sign << kSignShift);
    }
    return table;
}();
inline uint8_t min_max_choice(long long predicates) { return kMinMaxChoices[predicates & 63]; }

/// Only min, max, select and the R-operations choose an operand.
inline bool may_choose(ir::Op op) {
    return op == ir::Op::Min || op == ir::Op::Max || op == ir::Op::Select || op == ir::Op::RAnd ||
           op == ir::Op::ROr;
}

}  // namespace box_choice

/// The choice byte of `ins`, whose result ranges over `out` and whose operands (immediates
/// included) over a, b, c over the box.
inline uint8_t instruction_choice(const Instruction& ins, const Interval& out, const Interval& a, const Interval& b,
                                  const Interval& c) {
    using namespace box_choice;
    // ±1 stands for a value of one sign only where it is finite: an R-formula of ±inf is NaN.
    const bool finite = out.bounded();
    uint8_t choice = (out.positive() && finite ? kPositive : 0) | (out.negative() && finite ? kNegative : 0);
    if (!may_choose(ins.op)) return choice | kUndecided;
    const int value = chosen_operand(ins, a, b, c, false);
    const int sign = value != kNone ? value : chosen_operand(ins, a, b, c, true);
    return choice | static_cast<uint8_t>(value << kValueShift) | static_cast<uint8_t>(sign << kSignShift);
}

}  // namespace fortu
