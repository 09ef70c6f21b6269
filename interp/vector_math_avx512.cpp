// interp/vector_math_avx512.cpp — vector_math.def's kernels on 16 float32 lanes (AVX-512F),
// compiled with -mavx512f whatever the build's -march (CMakeLists.txt); used only when
// the CPU has them (vector_math.cpp). Includes nothing but SLEEF and the intrinsics (see
// vector_math_kernels.hpp for why).
#include "interp/vector_math_kernels.hpp"

#include <immintrin.h>
#include <sleef.h>

namespace fortu::vector_math {
namespace {

/// The lane loop: whole vectors, then the remainder through masked loads and stores
/// (masked-off lanes read 0.0f, which no SLEEF function traps on).
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

#define FORTU_VECTOR_MATH_1(op, sleef, accuracy, ulp, lo, hi)                                     \
    void op(const float* a, const float*, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop([](__m512 x, __m512) { return Sleef_##sleef##f16_##accuracy##avx512f(x); },       \
                   a, nullptr, ka, kb, mask, out, n);                                                  \
    }
#define FORTU_VECTOR_MATH_2(op, sleef, accuracy, ulp, lo, hi)                                     \
    void op(const float* a, const float* b, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop([](__m512 x, __m512 y) { return Sleef_##sleef##f16_##accuracy##avx512f(x, y); },  \
                   a, b, ka, kb, mask, out, n);                                                  \
    }
#include "interp/vector_math.def"

}  // namespace

const Kernel kAvx512Kernels[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, sleef, accuracy, ulp, lo, hi) &op,
#define FORTU_VECTOR_MATH_2(op, sleef, accuracy, ulp, lo, hi) &op,
#include "interp/vector_math.def"
};

}  // namespace fortu::vector_math
