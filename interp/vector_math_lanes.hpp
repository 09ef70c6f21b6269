// interp/vector_math_lanes.hpp — the loop that runs one vector function over an array of
// float32 lanes, written once for vector_math_avx2.cpp and vector_math_avx512.cpp: whole
// vectors, then the remainder through masked loads and stores. Includes nothing
// (vector_math_kernels.hpp says why); `W` is the ISA's lane type of
// vector_math_functions.hpp, with in addition: kWidth (lanes per vector), Tail (a mask of the
// first lanes), tail(remaining), load(p), load(p, tail), store(p, v), store(p, tail, v).
#pragma once

namespace fortu::vector_math {

/// out[l] = f(a[l], b[l]) for l < lanes, an operand whose bit is set in `mask` (bit 0: a,
/// bit 1: b) being ka / kb in every lane, b unused when null. Masked-off lanes of the
/// remainder read 0.0f, which no function traps on. With kTwoResults, f gives a pair (SLEEF's
/// sincos: .x, .y), its second written to second_out.
template <class W, bool kTwoResults = false, class F>
inline void lanes_loop(F f, const float* a, const float* b, float ka, float kb, unsigned mask, float* out,
                       int lanes, float* second_out = nullptr) {
    const typename W::F va = W::set(ka);
    const typename W::F vb = W::set(kb);
    const bool a_constant = (mask & 1) != 0;
    const bool b_constant = (mask & 2) != 0 || b == nullptr;
    const auto put = [&](int l, const auto& result, const auto&... tail) {
        if constexpr (kTwoResults) {
            W::store(out + l, tail..., result.x);
            W::store(second_out + l, tail..., result.y);
        } else {
            W::store(out + l, tail..., result);
        }
    };
    int l = 0;
    for (; l + W::kWidth <= lanes; l += W::kWidth)
        put(l, f(a_constant ? va : W::load(a + l), b_constant ? vb : W::load(b + l)));
    if (l < lanes) {
        const typename W::Tail keep = W::tail(lanes - l);
        put(l, f(a_constant ? va : W::load(a + l, keep), b_constant ? vb : W::load(b + l, keep)), keep);
    }
}

}  // namespace fortu::vector_math
