// interp/vector_math_avx512.cpp — vector_math.def's kernels on 16 float32 lanes (AVX-512F),
// compiled with -mavx512f whatever the build's -march (CMakeLists.txt); used only when
// the CPU has them (vector_math.cpp). Includes nothing but SLEEF, the intrinsics and
// vector_math_functions.hpp (see vector_math_kernels.hpp for why). fortu's own functions
// are the AVX2 file's templates on 16 lanes: the same operations, so the same values.
#include "interp/vector_math_kernels.hpp"
#include "interp/vector_math_functions.hpp"
#include "interp/vector_math_lanes.hpp"

#include <immintrin.h>
#include <sleef.h>

// GCC 12 warns that the _mm512_undefined_* operands inside intrinsics such as
// _mm512_cvtepi32_ps and _mm512_srai_epi32 may be uninitialized: they are meant to be.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace fortu::vector_math {
namespace {

/// 16 float32 lanes (AVX-512F only) for vector_math_functions.hpp's templates.
struct Avx512 {
    using F = __m512;
    using I = __m512i;
    using M = __mmask16;
    static F set(float v) { return _mm512_set1_ps(v); }
    static I seti(int v) { return _mm512_set1_epi32(v); }
    static F add(F a, F b) { return _mm512_add_ps(a, b); }
    static F sub(F a, F b) { return _mm512_sub_ps(a, b); }
    static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
    static F fma(F a, F b, F c) { return _mm512_fmadd_ps(a, b, c); }
    static F fnma(F a, F b, F c) { return _mm512_fnmadd_ps(a, b, c); }
    static F min(F a, F b) { return _mm512_min_ps(a, b); }
    static F max(F a, F b) { return _mm512_max_ps(a, b); }
    static F abs(F a) { return _mm512_abs_ps(a); }
    static F to_float(I a) { return _mm512_cvtepi32_ps(a); }
    static F as_float(I a) { return _mm512_castsi512_ps(a); }
    static I as_int(F a) { return _mm512_castps_si512(a); }
    static I addi(I a, I b) { return _mm512_add_epi32(a, b); }
    static I subi(I a, I b) { return _mm512_sub_epi32(a, b); }
    static I andi(I a, I b) { return _mm512_and_si512(a, b); }
    static I shl23(I a) { return _mm512_slli_epi32(a, 23); }
    static I sra1(I a) { return _mm512_srai_epi32(a, 1); }
    static I sra23(I a) { return _mm512_srai_epi32(a, 23); }
    static M less(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
    static M greater(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
    static M equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
    static M not_less_equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_NLE_UQ); }
    static M not_greater_equal(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_NGE_UQ); }
    static M or_mask(M a, M b) { return static_cast<M>(a | b); }
    static bool any(M m) { return m != 0; }
    static F select(M m, F if_true, F if_false) { return _mm512_mask_blend_ps(m, if_false, if_true); }
    static constexpr int kWidth = 16;
    using Tail = __mmask16;
    static Tail tail(int remaining) { return static_cast<Tail>((1u << remaining) - 1u); }
    static F load(const float* p) { return _mm512_loadu_ps(p); }
    static F load(const float* p, Tail keep) { return _mm512_maskz_loadu_ps(keep, p); }
    static void store(float* p, F v) { _mm512_storeu_ps(p, v); }
    static void store(float* p, Tail keep, F v) { _mm512_mask_storeu_ps(p, keep, v); }
};

// One vector through an op's function: SLEEF's, or fortu's own instantiated for 16 lanes.
#define FORTU_VECTOR_CALL_sleef(name, accuracy) Sleef_##name##f16_##accuracy##avx512f
#define FORTU_VECTOR_CALL_fortu(name, accuracy) functions::name<Avx512>

/// sin and cos of the same lanes from one reduction (vector_math.hpp, run_float_sincos).
void sincos_lanes(const float* a, float* sin_out, float* cos_out, int lanes) {
    lanes_loop<Avx512, true>([](Avx512::F x, Avx512::F) { return Sleef_sincosf16_u10avx512f(x); }, a, nullptr, 0.0f, 0.0f, 0, sin_out, lanes,
                          cos_out);
}

// fortu's own functions also as one-vector functions, for the AVX-512 compiled tapes (the
// lane loop's values bit for bit: the same code).
#define FORTU_VECTOR_ONE_sleef(op, name)
#define FORTU_VECTOR_ONE_fortu(op, name) \
    __m512 op##_vector(__m512 x) { return functions::name<Avx512>(x); }

#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi)                                \
    void op(const float* a, const float*, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop<Avx512>([](__m512 x, __m512) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x); },\
                   a, nullptr, ka, kb, mask, out, n);                                                  \
    }                                                                                                  \
    FORTU_VECTOR_ONE_##library(op, name)
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi)                                \
    void op(const float* a, const float* b, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop<Avx512>([](__m512 x, __m512 y) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x, y); },\
                   a, b, ka, kb, mask, out, n);                                                  \
    }
#include "interp/vector_math.def"

// What the AVX-512 compiled tapes call: SLEEF's function, or fortu's one-vector function above.
#define FORTU_VECTOR_ADDRESS_sleef(op, name, accuracy) reinterpret_cast<void*>(&Sleef_##name##f16_##accuracy##avx512f)
#define FORTU_VECTOR_ADDRESS_fortu(op, name, accuracy) reinterpret_cast<void*>(&op##_vector)

}  // namespace

const SinCosKernel kAvx512SinCos = &sincos_lanes;

const Kernel kAvx512Kernels[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) &op,
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) &op,
#include "interp/vector_math.def"
};

void* const kAvx512VectorFunctions[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) FORTU_VECTOR_ADDRESS_##library(op, name, accuracy),
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) FORTU_VECTOR_ADDRESS_##library(op, name, accuracy),
#include "interp/vector_math.def"
};

}  // namespace fortu::vector_math
