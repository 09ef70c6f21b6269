// interp/vector_math_kernels.hpp — the per-ISA kernel tables of vector_math.def, shared by
// the dispatcher (vector_math.cpp) and the translation units compiled for one ISA each
// (vector_math_avx2.cpp, vector_math_avx512.cpp). Why a header with no includes: a
// translation unit compiled with -mavx512f must not emit inline functions of shared
// headers (the linker could keep its AVX-512 copy for the whole program).
#pragma once

namespace fortu::vector_math {

/// One entry per line of vector_math.def, in its order.
enum Slot : int {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) k##op,
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) k##op,
#include "interp/vector_math.def"
    kSlotCount
};

/// out[l] = op(a[l], b[l]) for l < lanes; an operand whose bit is set in constant_mask
/// (bit 0: a, bit 1: b) is ka / kb in every lane; b is unused by one-operand ops.
using Kernel = void (*)(const float* a, const float* b, float ka, float kb, unsigned constant_mask,
                        float* out, int lanes);

extern const Kernel kAvx2Kernels[kSlotCount];
extern const Kernel kAvx512Kernels[kSlotCount];

/// sin_out[l] = sin(a[l]), cos_out[l] = cos(a[l]) for l < lanes, both from one SLEEF sincos.
using SinCosKernel = void (*)(const float* a, float* sin_out, float* cos_out, int lanes);
extern const SinCosKernel kAvx2SinCos;
extern const SinCosKernel kAvx512SinCos;
/// Each op's function on one AVX2 vector (SysV: operands in ymm0, ymm1, result in ymm0),
/// the one kAvx2Kernels calls, for the compiled tapes.
extern void* const kAvx2VectorFunctions[kSlotCount];
/// The same for AVX-512 (zmm0, zmm1, result in zmm0), the one kAvx512Kernels calls.
extern void* const kAvx512VectorFunctions[kSlotCount];

}  // namespace fortu::vector_math
