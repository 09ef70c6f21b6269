// interp/float32_bound.hpp — how far a tape's float32 evaluation can be from its float64
// evaluation over a box: the sign renderer's leaves run in float32 (twice the lanes per
// vector, SLEEF's vector transcendentals instead of scalar libm) and keep the float32 sign
// wherever |value| exceeds this bound; the other points are evaluated again in float64.
//
// Why a bound and not a tolerance: the sign image must equal the float64 evaluation's signs
// point for point. A forward error analysis over the box's slot ranges (interval.hpp) gives,
// per slot, e ≥ |v32 − v64| at every point of the box: the operands' e carried through the
// operation's Lipschitz bound over the operand ranges widened by their e, plus the rounding
// of the result in both formats (correctly rounded arithmetic: 2^-24 and 2^-53 of its
// magnitude; SLEEF's and libm's functions: 2^-22 and 2^-50), plus an absolute term for
// float32's subnormal range. A value whose range is infinite (a pole in the box) keeps the
// range of its float32 values instead, until a result whose two ranges are finite gets their
// hull's width as its bound. An operation without a rule (pow, tan, mod, select, …) or a range
// that may be NaN gives +inf: that box runs in float64.
#pragma once

#include "interp/interval.hpp"
#include "interp/tape.hpp"

#include <vector>

namespace fortu {

/// The bound on |float32 − float64| of `tape`'s root over a box, where `ranges` are the
/// ranges of the tape's slots over that box (evaluate_intervals); +inf when not bounded.
/// `errors` is working memory (one bound per slot).
double float32_error_bound(const Tape& tape, const std::vector<Interval>& ranges, std::vector<double>& errors);

}  // namespace fortu
