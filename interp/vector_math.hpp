// interp/vector_math.hpp — float32 transcendentals on whole lane arrays with vector
// functions (the ops of vector_math.def: SLEEF's, or fortu's own for exp and ln), on the
// widest instruction set this CPU has: AVX-512 where it exists, AVX2 + FMA otherwise, chosen
// once at run time. Why: a lane loop that calls libm once per lane spends most of its time
// there (bear.vm: 29 exp and 8 log per point); a vector function computes 8 or 16 lanes in
// about the time libm takes for one.
// float64 does not come here: it keeps libm on every path (vector_math.def says why).
#pragma once

#include "interp/ir/ir.hpp"

#include <string>

namespace fortu::vector_math {

enum class Isa { none, avx2, avx512 };

/// Whether `op` is in vector_math.def (its float32 lane loop may come here).
constexpr bool has_vector_kernel(ir::Op op) {
    switch (op) {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) case ir::Op::op:
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) case ir::Op::op:
#include "interp/vector_math.def"
        return true;
    default:
        return false;
    }
}

/// Whether `op`'s float32 lanes run fortu's own function (vector_math_functions.hpp: the
/// list's library column says `fortu`), which compiled tapes then write inline.
constexpr bool runs_fortu_function(ir::Op op) {
#define FORTU_LIBRARY_IS_fortu true
#define FORTU_LIBRARY_IS_sleef false
    switch (op) {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) \
    case ir::Op::op: return FORTU_LIBRARY_IS_##library;
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) \
    case ir::Op::op: return FORTU_LIBRARY_IS_##library;
#include "interp/vector_math.def"
    default:
        return false;
    }
#undef FORTU_LIBRARY_IS_fortu
#undef FORTU_LIBRARY_IS_sleef
}

/// The widest ISA both this build and this CPU support.
Isa best_isa();
/// The ISA run_float uses (best_isa() unless narrowed by use_isa).
Isa active_isa();
/// Narrows the ISA (tests compare the variants; `none` makes run_float refuse); an ISA
/// wider than best_isa() gives best_isa(). Not thread-safe: call before evaluating.
void use_isa(Isa isa);
/// "AVX-512", "AVX2" or "none".
const char* isa_name(Isa isa);
/// Whose functions compute the float32 transcendentals, from the list's library column:
/// "SLEEF; exp, ln: fortu".
std::string libraries_text();

/// out[l] = op(a[l], b[l]) for l < lanes; an operand whose bit is set in constant_mask is
/// ka / kb in every lane. False (nothing written) when op has no vector kernel or no
/// vector ISA is active: the caller runs its own lane loop.
bool run_float(ir::Op op, const float* a, const float* b, float ka, float kb, unsigned constant_mask,
               float* out, int lanes);

/// sin_out[l] = sin(a[l]) and cos_out[l] = cos(a[l]) for l < lanes from one SLEEF sincos
/// (the same 1-ULP class as Sin and Cos; its values may differ from theirs in the last bit,
/// so every path runs an adjacent sin and cos of one operand through it: lane_kernel.hpp,
/// tape_jit.cpp). Why: about 1.7 times faster than the two calls (one argument reduction),
/// and rotations and polar coordinates take both of one angle. False (nothing written)
/// when no vector ISA is active.
bool run_float_sincos(const float* a, float* sin_out, float* cos_out, int lanes);

/// The function run_float's kernel of `isa` applies to each vector (AVX2: 8 lanes, operands
/// in ymm0 and ymm1, the result in ymm0; AVX-512: 16 lanes in zmm0, zmm1, zmm0), for the
/// compiled tapes of that width; nullptr when `op` has none or this build has no kernels of
/// that ISA.
void* one_vector_function(Isa isa, ir::Op op);

}  // namespace fortu::vector_math
