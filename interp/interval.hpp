// interp/interval.hpp — interval arithmetic on every IR operation, for interval-pruned
// rendering (sign_render.hpp): the value range of a node over a box of the domain.
//
// Contract: for every point of the box, the value the engines compute (double, the shared
// kernels) lies in [lo, hi], or is NaN only when `maybe_nan` is set; lo <= hi. A bound may be
// ±inf, and then the value itself may be ±inf there (1/x across x = 0 is [−∞, +∞], a number
// at every point; exp of it is [0, +∞]); a finite bound means every value is finite on that
// side. An operation whose range we do not bound gives kUnknownInterval (−∞..+∞, maybe NaN).
// Add, sub, mul, div, sqrt, min, max are correctly rounded and monotone, so their bounds
// hold exactly, overflow to ±inf included; ∞ − ∞, 0·∞, ∞/∞ and 0/0 set maybe_nan where an
// operand's range allows them; libm functions and the R-operations' formulas are widened by a
// few ulps. Users that need finite bounds (widths, midpoints, the R-formulas) ask bounded().
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
    /// Nothing known: any number, ±inf or NaN.
    bool unknown() const {
        return maybe_nan && lo == -std::numeric_limits<double>::infinity() &&
               hi == std::numeric_limits<double>::infinity();
    }
    /// Both bounds finite: every value is a finite number (or NaN, if maybe_nan).
    bool bounded() const {
        return lo > -std::numeric_limits<double>::infinity() && hi < std::numeric_limits<double>::infinity();
    }
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
