// interp/interval.cpp — the interval kernels: the rules ops.def's interval column names,
// dispatched by a switch generated from ops.def (one case per operation, no default). An
// operation whose rule is not_bounded() gets kUnknownInterval, which is always correct:
// pruning then simply does not happen for that node. Bounds may be ±inf (interval.hpp): each
// rule says what its operation does with infinite values (IEEE: x/0 = ±∞, ∞ − ∞, 0·∞, ∞/∞
// and 0/0 are NaN); pow and the R-formulas with α ≠ 1 keep finite operands only.
#include "interp/interval.hpp"

#include "interp/ir/kernels.hpp"
#include "interp/tape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fortu {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The arithmetic rules, inlined into the tape loop's switch: left to itself the compiler
/// called product, quotient and squared out of line (bear.vm: 5% of the sign volume's
/// instructions in those calls alone).
#define FORTU_INTERVAL_INLINE inline __attribute__((always_inline))

/// Widening for libm results (not guaranteed correctly rounded): a few ulps each way. A bound
/// of ±inf stays (∓inf widens outward to itself); a low bound of +inf (f overflowed at the
/// low end) becomes the largest double, a neighbouring point may have rounded below ∞.
Interval widened(double lo, double hi, bool maybe_nan) {
    constexpr double kMax = std::numeric_limits<double>::max();
    return {lo == kInf ? kMax : lo - std::abs(lo) * 8 * kEps, hi == -kInf ? -kMax : hi + std::abs(hi) * 8 * kEps,
            maybe_nan};
}

/// A safety net: a bound that came out NaN (or crossed) means the rule did not apply.
FORTU_INTERVAL_INLINE Interval checked(Interval r) {
    if (!(r.lo <= r.hi)) return kUnknownInterval;
    return r;
}

/// For the rules that keep finite values only (pow, the R-formulas): anything else unknown.
FORTU_INTERVAL_INLINE Interval finite_or_unknown(Interval r) {
    if (!std::isfinite(r.lo) || !std::isfinite(r.hi) || r.lo > r.hi) return kUnknownInterval;
    return r;
}

bool contains_zero(const Interval& a) { return a.lo <= 0 && a.hi >= 0; }

FORTU_INTERVAL_INLINE Interval from_corners(double p, double q, double r, double s, bool maybe_nan) {
    return {std::min({p, q, r, s}), std::max({p, q, r, s}), maybe_nan};
}

/// Whether some t0 + k·period (k integer) lies in [lo, hi].
bool contains_periodic(double lo, double hi, double t0, double period) {
    const double k = std::ceil((lo - t0) / period - 1e-9);
    return t0 + k * period <= hi + 1e-9;
}

Interval sin_interval(const Interval& a, double shift) {
    // sin(x + shift): maxima where x + shift = π/2 + 2kπ, minima at -π/2 + 2kπ.
    constexpr double kPi = std::numbers::pi;
    if (a.hi - a.lo >= 2 * kPi) return {-1.0, 1.0, a.maybe_nan};
    const double p = shift == 0 ? std::sin(a.lo) : std::cos(a.lo);
    const double q = shift == 0 ? std::sin(a.hi) : std::cos(a.hi);
    Interval r = widened(std::min(p, q), std::max(p, q), a.maybe_nan);
    if (contains_periodic(a.lo, a.hi, kPi / 2 - shift, 2 * kPi)) r.hi = 1.0;
    if (contains_periodic(a.lo, a.hi, -kPi / 2 - shift, 2 * kPi)) r.lo = -1.0;
    r.lo = std::max(r.lo, -1.0);
    r.hi = std::min(r.hi, 1.0);
    return r;
}

/// R-conjunction/disjunction: monotone non-decreasing in both operands for every alpha in
/// (-1, 1] (∂/∂a = (1 ∓ (a − αb)/√(a² + b² − 2αab))/(1 + α) ≥ 0), so the range is the
/// formula at the low and high corners; widened by the formula's rounding error, a few
/// ulps of the operands' magnitude.
Interval r_interval(bool conjunction, const Interval& a, const Interval& b, double alpha) {
    if (alpha == 1.0)
        return conjunction ? Interval{std::min(a.lo, b.lo), std::min(a.hi, b.hi), a.maybe_nan || b.maybe_nan}
                           : Interval{std::max(a.lo, b.lo), std::max(a.hi, b.hi), a.maybe_nan || b.maybe_nan};
    auto r = [&](double x, double y) {
        return conjunction ? ir::r_conjunction(ir::value_of(x), ir::value_of(y), alpha)
                           : ir::r_disjunction(ir::value_of(x), ir::value_of(y), alpha);
    };
    const double scale = std::max(std::abs(a.lo), std::abs(a.hi)) + std::max(std::abs(b.lo), std::abs(b.hi));
    const double margin = 32 * kEps * scale;
    return {r(a.lo, b.lo) - margin, r(a.hi, b.hi) + margin, a.maybe_nan || b.maybe_nan};
}

// ---- the rules ops.def's interval column names ----

Interval not_bounded() { return kUnknownInterval; }
FORTU_INTERVAL_INLINE Interval negated(const Interval& a) { return {-a.hi, -a.lo, a.maybe_nan}; }
/// a + b: monotone rounding, so the bounds' sums bound the values' sums (an overflow included).
/// ∞ + (−∞) is NaN: possible where one range reaches +∞ and the other −∞.
Interval infinite_sum(const Interval& a, const Interval& b) {
    const bool opposite_infinities = (a.hi == kInf && b.lo == -kInf) || (a.lo == -kInf && b.hi == kInf);
    Interval r{a.lo + b.lo, a.hi + b.hi, a.maybe_nan || b.maybe_nan || opposite_infinities};
    if (std::isnan(r.lo)) r.lo = -kInf;  // −∞ + ∞ at the bound: the values there are NaN or +∞
    if (std::isnan(r.hi)) r.hi = kInf;
    return r;
}
FORTU_INTERVAL_INLINE Interval sum(const Interval& a, const Interval& b) {
    const Interval r{a.lo + b.lo, a.hi + b.hi, a.maybe_nan || b.maybe_nan};
    // Finite bounds of the sum: the operands' were finite, so no ∞ − ∞ (the common case).
    if (std::abs(r.lo) < kInf && std::abs(r.hi) < kInf) return r;
    return infinite_sum(a, b);
}
/// a − b = a + (−b), bit for bit.
FORTU_INTERVAL_INLINE Interval difference(const Interval& a, const Interval& b) { return sum(a, negated(b)); }

/// Products with an infinite bound (out of line: rare). 0·∞ is NaN at a point; as a corner it
/// stands for the products near it, whose extremes the other corners already give (x·y is
/// monotone in each operand with the other fixed), so it counts as 0.
Interval infinite_product(const Interval& a, const Interval& b, bool maybe_nan) {
    auto corner = [](double x, double y) { return (x == 0 || y == 0) ? 0.0 : x * y; };
    maybe_nan = maybe_nan || (contains_zero(a) && !b.bounded()) || (contains_zero(b) && !a.bounded());
    return from_corners(corner(a.lo, b.lo), corner(a.lo, b.hi), corner(a.hi, b.lo), corner(a.hi, b.hi), maybe_nan);
}
FORTU_INTERVAL_INLINE Interval product(const Interval& a, const Interval& b) {
    const bool maybe_nan = a.maybe_nan || b.maybe_nan;
    if (!a.bounded() || !b.bounded()) return infinite_product(a, b, maybe_nan);
    return from_corners(a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi, maybe_nan);  // ±inf on overflow
}
/// Quotients with a pole or an infinite bound (out of line: rare).
Interval pole_quotient(const Interval& a, const Interval& b, bool maybe_nan) {
    const bool both_infinite = !a.bounded() && !b.bounded();   // ∞/∞ is NaN
    if (b.lo > 0 || b.hi < 0) {
        // x/y is monotone in each operand on one side of 0: the corners bound it. An ∞/∞
        // corner stands for the quotients near it: anything from 0 to ∞ of its sign.
        Interval r{kInf, -kInf, maybe_nan || both_infinite};
        for (const double x : {a.lo, a.hi})
            for (const double y : {b.lo, b.hi}) {
                const double q = x / y;
                if (std::isnan(q)) {
                    const double far = (x > 0) == (y > 0) ? kInf : -kInf;
                    r.lo = std::min({r.lo, 0.0, far});
                    r.hi = std::max({r.hi, 0.0, far});
                } else {
                    r.lo = std::min(r.lo, q);
                    r.hi = std::max(r.hi, q);
                }
            }
        return r;
    }
    // b may be 0, or −0: x/±0 is ±∞ of either sign, 0/0 is NaN.
    if (a.lo == 0 && a.hi == 0) return {0.0, 0.0, true};   // 0/y = ±0 where y ≠ 0
    return {-kInf, kInf, maybe_nan || contains_zero(a) || both_infinite};
}
FORTU_INTERVAL_INLINE Interval quotient(const Interval& a, const Interval& b) {
    const bool maybe_nan = a.maybe_nan || b.maybe_nan;
    if (!(b.lo > 0 || b.hi < 0) || !a.bounded() || !b.bounded()) return pole_quotient(a, b, maybe_nan);
    return from_corners(a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi, maybe_nan);  // ±inf on overflow
}
Interval power(const Interval& a, const Interval& b) {
    // std::pow's special values at ±inf and 0^-n are not worth rules: finite operands only.
    if (!a.bounded() || !b.bounded()) return kUnknownInterval;
    // A constant whole exponent n (X^2 in scripts): monotone in a for odd n, in |a|
    // for even n; std::pow is within an ulp there.
    if (b.lo == b.hi && !b.maybe_nan && b.lo == std::floor(b.lo) && std::abs(b.lo) <= 64 &&
        (b.lo > 0 || a.lo > 0 || a.hi < 0)) {
        const double n = b.lo;
        const bool even = std::fmod(n, 2.0) == 0;
        double lo = std::pow(a.lo, n), hi = std::pow(a.hi, n);
        if (lo > hi) std::swap(lo, hi);
        if (even && a.lo < 0 && a.hi > 0) lo = 0;  // n > 0 here (a straddles 0)
        return finite_or_unknown(widened(lo, hi, a.maybe_nan));
    }
    // a > 0: monotone in each operand, so the corners bound it.
    if (a.lo > 0) {
        const Interval r = from_corners(std::pow(a.lo, b.lo), std::pow(a.lo, b.hi), std::pow(a.hi, b.lo),
                                        std::pow(a.hi, b.hi), a.maybe_nan || b.maybe_nan);
        return finite_or_unknown(widened(r.lo, r.hi, r.maybe_nan));
    }
    return kUnknownInterval;
}
/// (±∞)² = +∞, an overflow +∞: no NaN from numbers.
FORTU_INTERVAL_INLINE Interval squared(const Interval& a) {
    if (a.lo >= 0) return {a.lo * a.lo, a.hi * a.hi, a.maybe_nan};
    if (a.hi <= 0) return {a.hi * a.hi, a.lo * a.lo, a.maybe_nan};
    return {0.0, std::max(a.lo * a.lo, a.hi * a.hi), a.maybe_nan};
}
FORTU_INTERVAL_INLINE Interval square_root(const Interval& a) {
    if (a.hi < 0) return kUnknownInterval;
    return {std::sqrt(std::max(a.lo, 0.0)), std::sqrt(a.hi), a.maybe_nan || a.lo < 0};
}
FORTU_INTERVAL_INLINE Interval absolute(const Interval& a) {
    if (a.lo >= 0) return a;
    if (a.hi <= 0) return {-a.hi, -a.lo, a.maybe_nan};
    return {0.0, std::max(-a.lo, a.hi), a.maybe_nan};
}
/// f non-decreasing (a libm function: widened); exp, atan, sinh, tanh are defined at ±∞
/// (exp(−∞) = 0).
Interval increasing(const Interval& a, double (*f)(double)) { return checked(widened(f(a.lo), f(a.hi), a.maybe_nan)); }
/// f non-decreasing where x ≥ 0, NaN below (logarithms: log(±0) = −∞, log(+∞) = +∞).
Interval increasing_above_zero(const Interval& a, double (*f)(double)) {
    if (!(a.lo >= 0)) return kUnknownInterval;
    return increasing(a, f);
}
/// f non-decreasing and exact (sign, floor, ceil: no rounding to widen for).
Interval exactly_increasing(const Interval& a, double (*f)(double)) { return {f(a.lo), f(a.hi), a.maybe_nan}; }
Interval arcsine(const Interval& a) {
    if (a.lo < -1 || a.hi > 1) return kUnknownInterval;
    return widened(std::asin(a.lo), std::asin(a.hi), a.maybe_nan);
}
Interval arccosine(const Interval& a) {
    if (a.lo < -1 || a.hi > 1) return kUnknownInterval;
    return widened(std::acos(a.hi), std::acos(a.lo), a.maybe_nan);
}
/// sin(±∞) is NaN.
Interval sine(const Interval& a, double shift) {
    if (!a.bounded()) return {-1.0, 1.0, true};
    return sin_interval(a, shift);
}
Interval hyperbolic_cosine(const Interval& a) {
    const double m = std::max(std::abs(a.lo), std::abs(a.hi));
    const double lo = (a.lo <= 0 && a.hi >= 0) ? 1.0 : std::cosh(std::min(std::abs(a.lo), std::abs(a.hi)));
    Interval r = checked(widened(lo, std::cosh(m), a.maybe_nan));
    if (!r.unknown()) r.lo = std::max(r.lo, 1.0);
    return r;
}
FORTU_INTERVAL_INLINE Interval minimum(const Interval& a, const Interval& b) {
    return {std::min(a.lo, b.lo), std::min(a.hi, b.hi), a.maybe_nan || b.maybe_nan};
}
FORTU_INTERVAL_INLINE Interval maximum(const Interval& a, const Interval& b) {
    return {std::max(a.lo, b.lo), std::max(a.hi, b.hi), a.maybe_nan || b.maybe_nan};
}
Interval hypotenuse(const Interval& a, const Interval& b) {
    auto low = [](const Interval& i) { return (i.lo <= 0 && i.hi >= 0) ? 0.0 : std::min(std::abs(i.lo), std::abs(i.hi)); };
    auto high = [](const Interval& i) { return std::max(std::abs(i.lo), std::abs(i.hi)); };
    Interval r = checked(widened(std::hypot(low(a), low(b)), std::hypot(high(a), high(b)), a.maybe_nan || b.maybe_nan));
    if (!r.unknown()) r.lo = std::max(r.lo, 0.0);
    return r;
}
/// SELECT(c, x, y) = x where c > 0, NaN where c is NaN, else y.
Interval selected(const Interval& c, const Interval& x, const Interval& y) {
    if (c.positive()) return x;
    if (c.hi <= 0 && !c.maybe_nan) return y;
    return {std::min(x.lo, y.lo), std::max(x.hi, y.hi), c.maybe_nan || x.maybe_nan || y.maybe_nan};
}
/// With α = 1 the R-operation is min/max (∞ allowed); the other formulas give ∞ − ∞ from an
/// infinite operand: finite operands and results only.
Interval r_operation(bool conjunction, const Interval& a, const Interval& b, double alpha) {
    if (alpha == 1.0) return r_interval(conjunction, a, b, alpha);
    if (!a.bounded() || !b.bounded()) return kUnknownInterval;
    return finite_or_unknown(r_interval(conjunction, a, b, alpha));
}

/// The rules' dispatch, inlined into the tape loop below (a call per instruction cost a
/// quarter of the interval pass).
inline __attribute__((always_inline)) Interval dispatch(ir::Op op, const Interval& a, const Interval& b,
                                                       const Interval& c, double imm) {
    using namespace ir;  // kernel names are used unqualified inside ops.def's interval column
    const int arity = op_arity(op);
    if (a.unknown() || (arity > 1 && b.unknown()) || (arity > 2 && c.unknown())) return kUnknownInterval;
    // Every operation has a case (no default): a new operation states its rule or not_bounded().
    switch (op) {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) \
    case Op::name: return (interval);
#include "interp/ir/ops.def"
    }
    return kUnknownInterval;
}

}  // namespace

Interval interval_op(ir::Op op, const Interval& a, const Interval& b, const Interval& c, double imm) {
    return dispatch(op, a, b, c, imm);
}

void evaluate_intervals(const Tape& tape, const std::array<Interval, 3>& axes, std::vector<Interval>& ranges) {
    ranges.resize(tape.slot_count);
    for (auto [slot, axis] : tape.arguments) ranges[slot] = axes[axis];
    for (auto [slot, value] : tape.constants) ranges[slot] = {value, value, false};
    for (const Instruction& ins : tape.code) {
        if (ins.constant_operands == 0) {
            // The common case, without copies: unused operands read the zero slot's range.
            ranges[ins.out] = dispatch(ins.op, ranges[ins.in[0]], ranges[ins.in[1]], ranges[ins.in[2]], ins.imm);
            continue;
        }
        Interval immediate[ir::kMaxArity];
        const Interval* operand[ir::kMaxArity];
        for (int k = 0; k < ir::kMaxArity; ++k) {
            if ((ins.constant_operands >> k) & 1u) {
                immediate[k] = {ins.constant[k], ins.constant[k], false};
                operand[k] = &immediate[k];
            } else {
                operand[k] = &ranges[ins.in[k]];
            }
        }
        ranges[ins.out] = dispatch(ins.op, *operand[0], *operand[1], *operand[2], ins.imm);
    }
}

}  // namespace fortu
