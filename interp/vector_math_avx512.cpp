// interp/vector_math_avx512.cpp — vector_math.def's kernels on 16 float32 lanes (AVX-512F),
// compiled with -mavx512f whatever the build's -march (CMakeLists.txt); used only when
// the CPU has them (vector_math.cpp). Includes nothing but SLEEF, the intrinsics and
// vector_math_functions.hpp (see vector_math_kernels.hpp for why). fortu's own functions
// are the AVX2 file's templates on 16 lanes: the same operations, so the same values.
#include "interp/vector_math_kernels.hpp"
#include "interp/vector_math_functions.hpp"

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
};

// One vector through an op's function: SLEEF's, or fortu's own instantiated for 16 lanes.
#define FORTU_VECTOR_CALL_sleef(name, accuracy) Sleef_##name##f16_##accuracy##avx512f
#define FORTU_VECTOR_CALL_fortu(name, accuracy) functions::name<Avx512>

/// The lane loop: whole vectors, then the remainder through masked loads and stores
/// (masked-off lanes read 0.0f, which no function traps on).
template <class F>
inline void lanes_loop(F f, const float* a, const float* b, float ka, float kb, unsigned mask,
                       float* out, int lanes) {
    const __m512 va = _mm512_set1_ps(ka);
    const __m512 vb = _mm512_set1_ps(kb);
    const bool a_constant = (mask & 1) != 0;
    const bool b_constant = (mask & 2) != 0 || b == nullptr;
    int l = 0;
    for (; l + 16 <= lanes; l += 16) {
        const __m512 x = a_constant ? va : _mm512_loadu_ps(a + l);
        const __m512 y = b_constant ? vb : _mm512_loadu_ps(b + l);
        _mm512_storeu_ps(out + l, f(x, y));
    }
    if (l < lanes) {
        const __mmask16 keep = static_cast<__mmask16>((1u << (lanes - l)) - 1u);
        const __m512 x = a_constant ? va : _mm512_maskz_loadu_ps(keep, a + l);
        const __m512 y = b_constant ? vb : _mm512_maskz_loadu_ps(keep, b + l);
        _mm512_mask_storeu_ps(out + l, keep, f(x, y));
    }
}

#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi)                                \
    void op(const float* a, const float*, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop([](__m512 x, __m512) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x); },\
                   a, nullptr, ka, kb, mask, out, n);                                                  \
    }
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi)                                \
    void op(const float* a, const float* b, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop([](__m512 x, __m512 y) { return FORTU_VECTOR_CALL_##library(name, accuracy)(x, y); },\
                   a, b, ka, kb, mask, out, n);                                                  \
    }
#include "interp/vector_math.def"

}  // namespace

const Kernel kAvx512Kernels[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) &op,
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) &op,
#include "interp/vector_math.def"
};

}  // namespace fortu::vector_math
