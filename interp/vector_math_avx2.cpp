// interp/vector_math_avx2.cpp — vector_math.def's kernels on 8 float32 lanes (AVX2 + FMA),
// compiled with -mavx2 -mfma whatever the build's -march (CMakeLists.txt); used only when
// the CPU has them (vector_math.cpp). Includes nothing but SLEEF, the intrinsics and
// vector_math_functions.hpp (see vector_math_kernels.hpp for why).
#include "interp/vector_math_kernels.hpp"
#include "interp/vector_math_functions.hpp"
#include "interp/vector_math_lanes.hpp"

#include <immintrin.h>
#include <sleef.h>

namespace fortu::vector_math {
namespace {

/// 8 float32 lanes for vector_math_functions.hpp's templates.
struct Avx2 {
    using F = __m256;
    using I = __m256i;
    using M = __m256;
    static F set(float v) { return _mm256_set1_ps(v); }
    static I seti(int v) { return _mm256_set1_epi32(v); }
    static F add(F a, F b) { return _mm256_add_ps(a, b); }
    static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
    static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
    static F fma(F a, F b, F c) { return _mm256_fmadd_ps(a, b, c); }
    static F fnma(F a, F b, F c) { return _mm256_fnmadd_ps(a, b, c); }
    static F min(F a, F b) { return _mm256_min_ps(a, b); }
    static F max(F a, F b) { return _mm256_max_ps(a, b); }
    static F abs(F a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
    static F to_float(I a) { return _mm256_cvtepi32_ps(a); }
    static F as_float(I a) { return _mm256_castsi256_ps(a); }
    static I as_int(F a) { return _mm256_castps_si256(a); }
    static I addi(I a, I b) { return _mm256_add_epi32(a, b); }
    static I subi(I a, I b) { return _mm256_sub_epi32(a, b); }
    static I andi(I a, I b) { return _mm256_and_si256(a, b); }
    static I shl23(I a) { return _mm256_slli_epi32(a, 23); }
    static I sra1(I a) { return _mm256_srai_epi32(a, 1); }
    static I sra23(I a) { return _mm256_srai_epi32(a, 23); }
    static M less(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
    static M greater(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
    static M equal(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
    static M not_less_equal(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_NLE_UQ); }
    static M not_greater_equal(F a, F b) { return _mm256_cmp_ps(a, b, _CMP_NGE_UQ); }
    static M or_mask(M a, M b) { return _mm256_or_ps(a, b); }
    static bool any(M m) { return _mm256_movemask_ps(m) != 0; }
    static F select(M m, F if_true, F if_false) { return _mm256_blendv_ps(if_false, if_true, m); }
    static constexpr int kWidth = 8;
    using Tail = __m256i;
    static Tail tail(int remaining) {
        return _mm256_cmpgt_epi32(_mm256_set1_epi32(remaining), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    }
    static F load(const float* p) { return _mm256_loadu_ps(p); }
    static F load(const float* p, Tail keep) { return _mm256_maskload_ps(p, keep); }
    static void store(float* p, F v) { _mm256_storeu_ps(p, v); }
    static void store(float* p, Tail keep, F v) { _mm256_maskstore_ps(p, keep, v); }
};

// One vector through an op's function: SLEEF's, or fortu's own instantiated for 8 lanes.
#define FORTU_VECTOR_CALL_sleef(name, accuracy) Sleef_##name##f8_##accuracy##avx2
#define FORTU_VECTOR_CALL_fortu(name, accuracy) functions::name<Avx2>

/// sin and cos of the same lanes from one reduction (vector_math.hpp, run_float_sincos).
void sincos_lanes(const float* a, float* sin_out, float* cos_out, int lanes) {
    lanes_loop<Avx2, true>([](Avx2::F x, Avx2::F) { return Sleef_sincosf8_u10avx2(x); }, a, nullptr, 0.0f, 0.0f, 0, sin_out, lanes,
                          cos_out);
}

// fortu's own functions also as one-vector functions, for the compiled tapes (the lane
// loop's values bit for bit: the same code, no FMA contraction in ISO C++ mode).
#define FORTU_VECTOR_ONE_sleef(op, name)
#define FORTU_VECTOR_ONE_fortu(op, name) \
    __m256 op##_vector(__m256 x) { return functions::name<Avx2>(x); }

#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi)                              \
    void op(const float* a, const float*, float ka, float kb, unsigned mask, float* out, int n) {   \
        lanes_loop<Avx2>([](__m256 x, __m256) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x); }, \
                   a, nullptr, ka, kb, mask, out, n);                                               \
    }                                                                                               \
    FORTU_VECTOR_ONE_##library(op, name)
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi)                                    \
    void op(const float* a, const float* b, float ka, float kb, unsigned mask, float* out, int n) {       \
        lanes_loop<Avx2>([](__m256 x, __m256 y) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x, y); }, \
                   a, b, ka, kb, mask, out, n);                                                          \
    }
#include "interp/vector_math.def"

// What the compiled tapes call: SLEEF's function, or fortu's one-vector function above.
#define FORTU_VECTOR_ADDRESS_sleef(op, name, accuracy) reinterpret_cast<void*>(&Sleef_##name##f8_##accuracy##avx2)
#define FORTU_VECTOR_ADDRESS_fortu(op, name, accuracy) reinterpret_cast<void*>(&op##_vector)

}  // namespace

const Kernel kAvx2Kernels[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) &op,
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) &op,
#include "interp/vector_math.def"
};

const SinCosKernel kAvx2SinCos = &sincos_lanes;

void* const kAvx2VectorFunctions[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) FORTU_VECTOR_ADDRESS_##library(op, name, accuracy),
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) FORTU_VECTOR_ADDRESS_##library(op, name, accuracy),
#include "interp/vector_math.def"
};

}  // namespace fortu::vector_math
