// interp/vector_math_avx2.cpp — vector_math.def's kernels on 8 float32 lanes (AVX2 + FMA),
// compiled with -mavx2 -mfma whatever the build's -march (CMakeLists.txt); used only when
// the CPU has them (vector_math.cpp). Includes nothing but SLEEF, the intrinsics and
// vector_math_functions.hpp (see vector_math_kernels.hpp for why).
#include "interp/vector_math_kernels.hpp"
#include "interp/vector_math_functions.hpp"

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
};

// One vector through an op's function: SLEEF's, or fortu's own instantiated for 8 lanes.
#define FORTU_VECTOR_CALL_sleef(name, accuracy) Sleef_##name##f8_##accuracy##avx2
#define FORTU_VECTOR_CALL_fortu(name, accuracy) functions::name<Avx2>

/// The lane loop: whole vectors, then the remainder through masked loads and stores
/// (masked-off lanes read 0.0f, which no function traps on).
template <class F>
inline void lanes_loop(F f, const float* a, const float* b, float ka, float kb, unsigned mask,
                       float* out, int lanes) {
    const __m256 va = _mm256_set1_ps(ka);
    const __m256 vb = _mm256_set1_ps(kb);
    const bool a_constant = (mask & 1) != 0;
    const bool b_constant = (mask & 2) != 0 || b == nullptr;
    int l = 0;
    for (; l + 8 <= lanes; l += 8) {
        const __m256 x = a_constant ? va : _mm256_loadu_ps(a + l);
        const __m256 y = b_constant ? vb : _mm256_loadu_ps(b + l);
        _mm256_storeu_ps(out + l, f(x, y));
    }
    if (l < lanes) {
        const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        const __m256i keep = _mm256_cmpgt_epi32(_mm256_set1_epi32(lanes - l), lane);
        const __m256 x = a_constant ? va : _mm256_maskload_ps(a + l, keep);
        const __m256 y = b_constant ? vb : _mm256_maskload_ps(b + l, keep);
        _mm256_maskstore_ps(out + l, keep, f(x, y));
    }
}

// fortu's own functions also as one-vector functions, for the compiled tapes (the lane
// loop's values bit for bit: the same code, no FMA contraction in ISO C++ mode).
#define FORTU_VECTOR_ONE_sleef(op, name)
#define FORTU_VECTOR_ONE_fortu(op, name) \
    __m256 op##_vector(__m256 x) { return functions::name<Avx2>(x); }

#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi)                              \
    void op(const float* a, const float*, float ka, float kb, unsigned mask, float* out, int n) {   \
        lanes_loop([](__m256 x, __m256) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x); }, \
                   a, nullptr, ka, kb, mask, out, n);                                               \
    }                                                                                               \
    FORTU_VECTOR_ONE_##library(op, name)
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi)                                    \
    void op(const float* a, const float* b, float ka, float kb, unsigned mask, float* out, int n) {       \
        lanes_loop([](__m256 x, __m256 y) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x, y); }, \
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

void* const kAvx2VectorFunctions[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) FORTU_VECTOR_ADDRESS_##library(op, name, accuracy),
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) FORTU_VECTOR_ADDRESS_##library(op, name, accuracy),
#include "interp/vector_math.def"
};

}  // namespace fortu::vector_math
