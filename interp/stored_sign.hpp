// interp/stored_sign.hpp — a value's sign as the sign renderer stores it: a float64 sign
// (a Field) or the bit-inverted int8 code of a SignVolume (sign_render.hpp), one point or
// a leaf's row at a time.
//
// Why a header of its own: the row store is written by hand for the leaves' float32 rows,
// 16 wide in 2D and 8 in 3D (GCC 12 does not vectorise the narrowing to int8, and the
// lane-at-a-time loop was a tenth of prospero.vm's sign image and a fifth of tanglecube.vm's
// sign volume), and the NaN lanes it must handle never reach it through the renderer (a box
// that may be NaN runs in float64), so it is tested directly.
#pragma once

#include "interp/ir/kernels.hpp"

#include <cstdint>
#include <type_traits>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace fortu {

/// The stored sign of a value, without branches: 1, 0 (±0), -1 or NaN as a float64; as an
/// int8 the code ~sign, with NaN's 0x7f (~SignVolume::kNaN).
template <class Value, class F>
Value stored_sign_of(F v) {
    if constexpr (std::is_same_v<Value, double>) return double(ir::k_sign(v));
    else return static_cast<int8_t>(~(int((v > 0) - (v < 0)) | (int(v != v) << 7)));
}

#if defined(__AVX2__)
namespace stored_sign_detail {

/// The int8 codes of 8 float lanes, one per 32-bit lane: ~sign is gt − lt − 1 from the
/// compare masks (−1 or 0): −2 for 1, −1 for ±0, 0 for −1; NaN is 0x7f.
inline __m256i codes_of_8(const float* values) {
    const __m256 v = _mm256_loadu_ps(values), zero = _mm256_setzero_ps();
    const __m256i gt = _mm256_castps_si256(_mm256_cmp_ps(v, zero, _CMP_GT_OQ));
    const __m256i lt = _mm256_castps_si256(_mm256_cmp_ps(v, zero, _CMP_LT_OQ));
    const __m256i nan = _mm256_castps_si256(_mm256_cmp_ps(v, v, _CMP_UNORD_Q));
    const __m256i sign = _mm256_sub_epi32(_mm256_sub_epi32(gt, lt), _mm256_set1_epi32(1));
    return _mm256_blendv_epi8(sign, _mm256_set1_epi32(0x7f), nan);
}

/// Two vectors of codes narrowed to 16 bytes in lane order (packing saturates; the codes fit):
/// 32 → 16 bits gives, in 128-bit halves, lanes 0-3 8-11 | 4-7 12-15; 16 → 8 keeps that
/// order in 4-byte groups, which the shuffle puts right.
inline __m128i narrowed(__m256i first, __m256i second) {
    const __m256i words = _mm256_packs_epi32(first, second);
    const __m128i bytes = _mm_packs_epi16(_mm256_castsi256_si128(words), _mm256_extracti128_si256(words, 1));
    return _mm_shuffle_epi32(bytes, _MM_SHUFFLE(3, 1, 2, 0));
}

}  // namespace stored_sign_detail
#endif

/// stored_sign_of over a row of `width` values (kWidth when it is not 0). Restrict-qualified:
/// int8 stores may alias anything, and the compiler would not keep values in registers.
template <int kWidth, class Value, class F>
void store_sign_row(Value* __restrict out, const F* __restrict values, int width) {
#if defined(__AVX2__)
    // The leaves' rows (16 wide in 2D, 8 in 3D) by hand: GCC 12 does not vectorise the
    // narrowing to int8.
    if constexpr ((kWidth == 16 || kWidth == 8) && std::is_same_v<Value, int8_t> && std::is_same_v<F, float>) {
        using namespace stored_sign_detail;
        const __m256i first = codes_of_8(values);
        if constexpr (kWidth == 16) {
            _mm_storeu_si128(reinterpret_cast<__m128i*>(out), narrowed(first, codes_of_8(values + 8)));
        } else {
            _mm_storel_epi64(reinterpret_cast<__m128i*>(out), narrowed(first, first));
        }
        return;
    }
#endif
    if constexpr (kWidth > 0)
        for (int c = 0; c < kWidth; ++c) out[c] = stored_sign_of<Value>(values[c]);
    else
        for (int c = 0; c < width; ++c) out[c] = stored_sign_of<Value>(values[c]);
}

}  // namespace fortu
