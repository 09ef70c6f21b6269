// interp/vector_math_avx2.cpp — vector_math.def's kernels on 8 float32 lanes (AVX2 + FMA),
// compiled with -mavx2 -mfma whatever the build's -march (CMakeLists.txt); used only when
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

#define FORTU_VECTOR_MATH_1(op, sleef, accuracy, ulp, lo, hi)                                     \
    void op(const float* a, const float*, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop([](__m256 x, __m256) { return Sleef_##sleef##f8_##accuracy##avx2(x); },       \
                   a, nullptr, ka, kb, mask, out, n);                                                  \
    }
#define FORTU_VECTOR_MATH_2(op, sleef, accuracy, ulp, lo, hi)                                     \
    void op(const float* a, const float* b, float ka, float kb, unsigned mask, float* out, int n) { \
        lanes_loop([](__m256 x, __m256 y) { return Sleef_##sleef##f8_##accuracy##avx2(x, y); },  \
                   a, b, ka, kb, mask, out, n);                                                  \
    }
#include "interp/vector_math.def"

}  // namespace

const Kernel kAvx2Kernels[kSlotCount] = {
#define FORTU_VECTOR_MATH_1(op, sleef, accuracy, ulp, lo, hi) &op,
#define FORTU_VECTOR_MATH_2(op, sleef, accuracy, ulp, lo, hi) &op,
#include "interp/vector_math.def"
};

}  // namespace fortu::vector_math
