// interp/lane_kernel.hpp — the one lane kernel: a tape's instructions run over a batch of
// points (lanes), used by the voxel engine's tiles, the sign renderer's leaf boxes and the
// point evaluator's dual numbers.
#pragma once

#include "interp/ir/kernels.hpp"
#include "interp/tape.hpp"
#include "interp/vector_math.hpp"

#include <cstddef>
#include <type_traits>

namespace fortu {

/// Runs `code` over `lanes` points whose argument and input slots are filled; slots[s] is
/// slot s's lane array. The switch is outside the lane loop, so each case is a tight loop
/// the compiler vectorises (with kFixedLanes > 0 a fixed count, without remainder
/// handling); an operand that is a constant is read from a register, one loop per
/// combination that occurs after constant folding (none, the first or the second operand
/// constant). Every instruction's output slot differs from its operands' (tape.hpp), so
/// the lane arrays are `restrict`. float32 transcendentals go to vector_math.hpp.
template <class T, int kFixedLanes>
void run_lanes(const Instruction* code, std::size_t count, T* const* slots, int runtime_lanes) {
    using namespace ir;  // kernel names are used unqualified inside ops.def expressions
    const int lanes = kFixedLanes > 0 ? kFixedLanes : runtime_lanes;
    for (const Instruction* ins = code; ins != code + count; ++ins) {
        T* __restrict out = slots[ins->out];
        const T* __restrict A = slots[ins->in[0]];
        const T* __restrict B = slots[ins->in[1]];
        const T* __restrict C = slots[ins->in[2]];
        [[maybe_unused]] const double imm = ins->imm;
        [[maybe_unused]] const T ka = T(ins->constant[0]);
        [[maybe_unused]] const T kb = T(ins->constant[1]);
        [[maybe_unused]] const T kc = T(ins->constant[2]);
        const unsigned mask = ins->constant_operands;
        // float32 transcendentals: SLEEF's vectors instead of libm once per lane; a sin and
        // cos of one operand side by side both from one sincos.
        if constexpr (std::is_same_v<T, float>) {
            if (ins + 1 != code + count && sincos_twins(ins[0], ins[1])) {
                const bool sin_first = ins->op == Op::Sin;
                if (vector_math::run_float_sincos(A, slots[sin_first ? ins[0].out : ins[1].out],
                                                  slots[sin_first ? ins[1].out : ins[0].out], lanes)) {
                    ++ins;
                    continue;
                }
            }
            if (vector_math::has_vector_kernel(ins->op) &&
                vector_math::run_float(ins->op, A, B, ka, kb, mask, out, lanes))
                continue;
        }
        switch (ins->op) {
#define FORTU_LANES(expr, a_value, b_value, c_value)                       \
    for (int l = 0; l < lanes; ++l) {                                      \
        [[maybe_unused]] const T a = (a_value);                            \
        [[maybe_unused]] const T b = (b_value);                            \
        [[maybe_unused]] const T c = (c_value);                            \
        [[maybe_unused]] auto get_a = value_of(a);                         \
        [[maybe_unused]] auto get_b = value_of(b);                         \
        out[l] = (expr);                                                   \
    }
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) \
    case Op::name:                                                         \
        if (mask == 0) { FORTU_LANES(expr, A[l], B[l], C[l]) }             \
        else if (mask == 1) { FORTU_LANES(expr, ka, B[l], C[l]) }          \
        else if (mask == 2) { FORTU_LANES(expr, A[l], kb, C[l]) }          \
        else { FORTU_LANES(expr, (mask & 1) ? ka : A[l], (mask & 2) ? kb : B[l], (mask & 4) ? kc : C[l]) } \
        break;
#include "interp/ir/ops.def"
#undef FORTU_LANES
        }
    }
}

}  // namespace fortu
