// interp/number_operands.hpp — which operands of a tape's instructions are never NaN on a
// grid, so the tape compiler (tape_jit.hpp) may drop the NaN cases of MIN, MAX and SELECT.
//
// Why: MIN(a, b) must give a when a is NaN (k_min in ops.def: (a < b || a != a) ? a : b).
// x86's vminps gives (a < b) ? a : b, equal in every other case (NaN b, ±0 pairs included),
// so exact MIN costs a compare and a blend besides it on every vector. Where a is never NaN
// the one instruction is exact. prospero.vm's per-point tape is 2,878 MIN and MAX out of
// 4,196 operations: three instructions a vector instead of one.
//
// float64 values are the ones the interval contract covers (interval.hpp): an operand whose
// range over the grid's box is not `maybe_nan` is a number. float32 values differ from those
// by rounding, so there an operand is a number by a rule that holds in any precision: its
// operations are among those that give a number from numbers (+, −, ×, NEG, ABS, SQUARE,
// MIN, MAX, R0 and R-operations with α = 1; a square root of a value that is ≥ 0 by the same
// kind of rule) and a bound on its magnitude, carried with float32's rounding, stays below
// float32's largest value (no infinity, so no ∞ − ∞ or 0 × ∞). Anything else is not known to
// be a number.
#pragma once

#include "interp/engine.hpp"
#include "interp/ir/ir.hpp"
#include "interp/tape.hpp"
#include "runtime/grid.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fortu {

/// Bit k of result[i] is set when operand k of tape.code[i] is a number at every point of
/// `grid` with the tape run in `precision`. `tape` is compile_tape(graph, spec); the first
/// `opaque_inputs` of spec.inputs hold values from elsewhere (kept from an earlier run), not
/// known to be numbers; the others and the uniforms hold their nodes' values on this grid.
std::vector<uint8_t> number_operands(const ir::Graph& graph, const TapeSpec& spec, const Tape& tape, const Grid& grid,
                                     Precision precision, std::size_t opaque_inputs);

}  // namespace fortu
