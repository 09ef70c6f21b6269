// interp/box_intervals.cpp — the interval walk with choices: a short switch of inline rules
// for finite ranges, interval_op for the rest.
#include "interp/box_intervals.hpp"

#include "interp/box_choice.hpp"

#include <algorithm>
#include <cmath>

namespace fortu {
namespace {

using ir::Op;

#define FORTU_BOX_INLINE inline __attribute__((always_inline))

FORTU_BOX_INLINE bool finite(double v) { return std::abs(v) <= std::numeric_limits<double>::max(); }
/// Both operands' bounds finite (b: the zero slot's range for unary operations), without
/// branching on each.
FORTU_BOX_INLINE bool finite(const Interval& a, const Interval& b) {
    return finite(a.lo) & finite(a.hi) & finite(b.lo) & finite(b.hi);
}

/// The choice byte's sign bits (box_choice.hpp) of a result.
FORTU_BOX_INLINE uint8_t sign_bits(const Interval& r) {
    const uint8_t bits = static_cast<uint8_t>((r.lo > 0 ? box_choice::kPositive : 0) | (r.hi < 0 ? box_choice::kNegative : 0));
    return r.maybe_nan ? 0 : bits;
}

/// min(a, b) (max(a, b) with kMin false): box_choice::min_max_choice of its predicates.
template <bool kMin>
FORTU_BOX_INLINE uint8_t min_max_choice(const Interval& a, const Interval& b, const Interval& r) {
    const bool numbers = !a.maybe_nan && !b.maybe_nan;
    const long long predicates =
        kMin ? (numbers && a.hi < b.lo) | (numbers && b.hi < a.lo) << 1 | a.positive() << 2 | b.positive() << 3 |
                   (a.negative() && !b.maybe_nan) << 4 | (b.negative() && !a.maybe_nan) << 5
             : (numbers && a.lo > b.hi) | (numbers && b.lo > a.hi) << 1 | a.negative() << 2 | b.negative() << 3 |
                   (a.positive() && !b.maybe_nan) << 4 | (b.positive() && !a.maybe_nan) << 5;
    return box_choice::min_max_choice(predicates) | sign_bits(r);
}

/// Every other case: interval.cpp's rule and box_choice.hpp's choice, into range[ins.out].
/// Operands by value: taking their addresses kept the hot path's ranges on the stack.
__attribute__((noinline)) uint8_t general_rule(const Instruction& ins, double alo, double ahi, bool anan, double blo,
                                               double bhi, bool bnan, Interval* range) {
    const Interval a{alo, ahi, anan}, b{blo, bhi, bnan};
    const Interval c = ins.constant_operands & 4u ? Interval{ins.constant[2], ins.constant[2], false} : range[ins.in[2]];
    const Interval r = interval_op(ins.op, a, b, c, ins.imm);
    range[ins.out] = r;
    return instruction_choice(ins, r, a, b, c);
}

/// The rule of interval.cpp for ins.op on finite operands, written out, into `r` with the
/// choice byte; where that rule would meet a non-finite value or an empty range, and for
/// the operations not written out here, general_rule.
FORTU_BOX_INLINE uint8_t box_rule(const Instruction& ins, const Interval a, const Interval b, Interval* range) {
    using box_choice::kUndecided;
    const auto general = [&] { return general_rule(ins, a.lo, a.hi, a.maybe_nan, b.lo, b.hi, b.maybe_nan, range); };
    if (!finite(a, b)) return general();
    Interval& r = range[ins.out];
    const bool nan = a.maybe_nan || b.maybe_nan;
    double lo, hi;
    switch (ins.op) {
    case Op::Add:  // sum
        lo = a.lo + b.lo;
        hi = a.hi + b.hi;
        break;
    case Op::Sub:  // difference
        lo = a.lo - b.hi;
        hi = a.hi - b.lo;
        break;
    case Op::Mul: {  // product: from_corners
        const double p = a.lo * b.lo, q = a.lo * b.hi, s = a.hi * b.lo, t = a.hi * b.hi;
        lo = std::min({p, q, s, t});
        hi = std::max({p, q, s, t});
        break;
    }
    case Op::Square:  // squared
        if (a.lo >= 0) lo = a.lo * a.lo, hi = a.hi * a.hi;
        else if (a.hi <= 0) lo = a.hi * a.hi, hi = a.lo * a.lo;
        else lo = 0.0, hi = std::max(a.lo * a.lo, a.hi * a.hi);
        if (!(finite(lo) & finite(hi)) || lo > hi) return general();
        r = {lo, hi, a.maybe_nan};
        return kUndecided | sign_bits(r);
    case Op::Min:  // minimum
        r = {std::min(a.lo, b.lo), std::min(a.hi, b.hi), nan};
        return min_max_choice<true>(a, b, r);
    case Op::Max:  // maximum
        r = {std::max(a.lo, b.lo), std::max(a.hi, b.hi), nan};
        return min_max_choice<false>(a, b, r);
    case Op::Neg:  // negated
        r = {-a.hi, -a.lo, a.maybe_nan};
        return kUndecided | sign_bits(r);
    case Op::Sqrt:  // square_root
        if (a.hi < 0) return general();
        r = {std::sqrt(std::max(a.lo, 0.0)), std::sqrt(a.hi), a.maybe_nan || a.lo < 0};
        return kUndecided | sign_bits(r);
    case Op::Abs:  // absolute
        if (a.lo >= 0) r = a;
        else if (a.hi <= 0) r = {-a.hi, -a.lo, a.maybe_nan};
        else r = {0.0, std::max(-a.lo, a.hi), a.maybe_nan};
        return kUndecided | sign_bits(r);
    default:
        return general();
    }
    // sum, difference, product: checked()
    if (!(finite(lo) & finite(hi)) || lo > hi) return general();
    r = {lo, hi, nan};
    return kUndecided | sign_bits(r);
}

}  // namespace

void evaluate_box_intervals(const Tape& tape, const std::array<Interval, 3>& axes, std::vector<Interval>& ranges,
                            std::vector<uint8_t>& choices) {
    ranges.resize(tape.slot_count);
    choices.resize(tape.code.size());
    Interval* const range = ranges.data();
    uint8_t* const choice = choices.data();
    range[tape.zero_slot] = {0.0, 0.0, false};
    for (auto [slot, axis] : tape.arguments) range[slot] = axes[axis];
    for (auto [slot, value] : tape.constants) range[slot] = {value, value, false};
    const Instruction* const code = tape.code.data();
    const std::size_t count = tape.code.size();
    for (std::size_t i = 0; i < count; ++i) {
        const Instruction& ins = code[i];
        const unsigned immediate = ins.constant_operands;
        const Interval a = immediate & 1u ? Interval{ins.constant[0], ins.constant[0], false} : range[ins.in[0]];
        const Interval b = immediate & 2u ? Interval{ins.constant[1], ins.constant[1], false} : range[ins.in[1]];
        choice[i] = box_rule(ins, a, b, range);
    }
}

}  // namespace fortu
