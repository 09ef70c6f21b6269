// interp/interval.hpp — interval arithmetic on every IR operation, for interval-pruned
// rendering (sign_render.hpp): the value range of a node over a box of the domain.
//
// Contract: for every point of the box, the value the engines compute (double, the shared
// kernels) lies in [lo, hi], or is NaN only when `maybe_nan` is set. Bounds are always finite;
// an operation that could give ±inf, or whose range we do not bound, gives kUnknown. Add,
// sub, mul, div, sqrt, min, max are correctly rounded and monotone, so their bounds hold
// exactly; libm functions and the R-operations' formulas are widened by a few ulps.
#pragma once

#include "interp/ir/ir.hpp"

#include <array>
#include <limits>
#include <vector>

namespace fortu {

struct Interval {
    double lo = 0.0;
    double hi = 0.0;
    bool maybe_nan = false;

    /// Every point is > 0 (and a number).
    bool positive() const { return lo > 0 && !maybe_nan; }
    /// Every point is < 0 (and a number).
    bool negative() const { return hi < 0 && !maybe_nan; }
    bool unknown() const { return lo == -std::numeric_limits<double>::infinity(); }
};

inline constexpr Interval kUnknownInterval{-std::numeric_limits<double>::infinity(),
                                           std::numeric_limits<double>::infinity(), true};

/// The range of op(a, b, c) (imm: the node's immediate) given its operands' ranges.
/// Const and Arg are not handled here (the caller knows the box).
Interval interval_op(ir::Op op, const Interval& a, const Interval& b, const Interval& c, double imm);

struct Tape;

/// The range of every slot of `tape` over a box whose coordinates range over `axes`
/// (X, Y, Z). `tape` must be in SSA form (TapeSpec::reuse_slots false: one slot per value),
/// so `ranges[slot]` is the range of the one value that slot holds.
void evaluate_intervals(const Tape& tape, const std::array<Interval, 3>& axes, std::vector<Interval>& ranges);

}  // namespace fortu
