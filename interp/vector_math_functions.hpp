// interp/vector_math_functions.hpp — fortu's own float32 exp and ln on one SIMD vector, as
// templates over the vector width (vector_math_avx2.cpp and vector_math_avx512.cpp
// instantiate them with their intrinsics), used where vector_math.def says `fortu`.
// Why our own rather than SLEEF: on bear.vm (29 exp and 8 ln per point) SLEEF's exp and log
// were a third of the float32 evaluation; these take about half the time at the same
// 1-ULP bound (README, "Performance"). Highway's contrib math was measured too and was
// no faster for log (it divides), and needs the same special-value selects around it.
//
// Both are the classic reductions with FMA: exp by Cody–Waite (x = n·ln2 + r, |r| ≤ ln2/2),
// a degree-7 polynomial and 2^n from exponent bits (in two halves, so results from
// overflow down through the subnormals round once); ln by the exponent/mantissa split with
// the mantissa in [√½, √2) and a degree-10 polynomial in f = m − 1 (Cephes' logf).
// Special values are selected exactly: NaN → NaN, exp(+inf) = +inf, exp(−inf) = +0,
// ln(±0) = −inf, ln(x < 0) = NaN, ln(+inf) = +inf; subnormal arguments of ln are scaled
// by 2^23 first. The values do not depend on the width: the same IEEE operations in the
// same order (these files are compiled without FMA contraction).
//
// Includes nothing (vector_math_kernels.hpp says why); `W` supplies, for its vector type
// W::F, its integer vector W::I and its comparison mask W::M:
//   set(float), seti(int), add, sub, mul, fma(a, b, c) = a·b + c, fnma(a, b, c) = c − a·b,
//   min(a, b) / max(a, b) (b when either is NaN, as x86's minps/maxps), round_nearest,
//   to_int (F → I, exact on integers), as_float, as_int, addi, subi, andi, shl23, sra1,
//   sra23, abs, less, greater, equal (ordered comparisons), not_less_equal,
//   not_greater_equal (unordered or the opposite), or_mask, any(mask) (a lane is set),
//   select(mask, if_true, if_false).
#pragma once

namespace fortu::vector_math::functions {

namespace detail {

/// e^r for r = x − n·ln2, |r| ≤ ln2/2 (n = round(x / ln2)).
template <class W>
inline typename W::F exp_reduced(typename W::F x, typename W::F n) {
    using F = typename W::F;
    // r in two parts (ln2_hi·n is exact for |n| < 2^9).
    F r = W::fnma(n, W::set(0.693145751953125f), x);
    r = W::fnma(n, W::set(1.428606765330187045e-6f), r);
    // 1 + r + r²·P(r), P a degree-4 fit (relative error of the polynomial 3·10^-9, 0.05
    // ULP), by Horner with one rounding per step.
    F p = W::set(1.3814613e-3f);
    p = W::fma(p, r, W::set(8.3687100e-3f));
    p = W::fma(p, r, W::set(4.1668389e-2f));
    p = W::fma(p, r, W::set(1.6666521e-1f));
    p = W::fma(p, r, W::set(4.9999994e-1f));
    p = W::fma(p, r, W::set(1.0f));
    return W::fma(p, r, W::set(1.0f));
}

}  // namespace detail

namespace detail {

/// e^x for x in [−104, 89] or NaN (any other x: clamp first), the general case of exp.
template <class W>
inline typename W::F exp_wide(typename W::F x) {
    using F = typename W::F;
    using I = typename W::I;
    // n = round(x / ln2): adding 1.5·2^23 rounds to an integer, whose bits are then the
    // sum's low mantissa bits.
    const F shifter = W::set(12582912.0f);
    const F shifted = W::fma(x, W::set(1.44269502162933349609375f), shifter);
    const F n = W::sub(shifted, shifter);
    const F e_r = exp_reduced<W>(x, n);
    // 2^n = 2^(n/2) · 2^(n − n/2): each half a normal float for n in [−150, 129], so
    // results from overflow down through the subnormals round once.
    const I ni = W::subi(W::as_int(shifted), W::as_int(shifter));
    const I half = W::sra1(ni);
    const F scale_lo = W::as_float(W::shl23(W::addi(half, W::seti(127))));
    const F scale_hi = W::as_float(W::shl23(W::addi(W::subi(ni, half), W::seti(127))));
    return W::mul(W::mul(e_r, scale_lo), scale_hi);
}

}  // namespace detail

/// The lanes exp's narrow path does not cover: |x| > 87, or NaN (overflow, subnormal or
/// special results).
template <class W>
inline typename W::M exp_needs_wide(typename W::F x) {
    return W::not_less_equal(W::abs(x), W::set(87.0f));
}

/// e^x for |x| ≤ 87: n = round(x / ln2) and 2^n from one sum: 1.5·2^23 + 127 + x/ln2 rounds
/// to an integer whose low mantissa bits are n + 127, the biased exponent of 2^n.
template <class W>
inline typename W::F exp_narrow(typename W::F x) {
    using F = typename W::F;
    const F shifter = W::set(12583039.0f);
    const F shifted = W::fma(x, W::set(1.44269502162933349609375f), shifter);
    const F n = W::sub(shifted, shifter);
    return W::mul(detail::exp_reduced<W>(x, n), W::as_float(W::shl23(W::as_int(shifted))));
}

/// e^x, at most 1 float32 ULP from the exact value (vector_math.def).
template <class W>
inline typename W::F exp(typename W::F x) {
    // Beyond |x| = 87 (or NaN) a lane may overflow, be subnormal or be special: the wide
    // path, whose clamp gives +inf above 89 > ln(FLT_MAX) and +0 below −104 (e^-104 <
    // 2^-150). NaN passes the clamp (min/max give their second operand).
    if (W::any(exp_needs_wide<W>(x))) [[unlikely]]
        return detail::exp_wide<W>(W::max(W::set(-104.0f), W::min(W::set(89.0f), x)));
    return exp_narrow<W>(x);
}

namespace detail {

/// ln x for a positive normal x, plus `exponent_adjust` · ln2.
template <class W>
inline typename W::F log_normal(typename W::F x, typename W::F exponent_adjust) {
    using F = typename W::F;
    using I = typename W::I;
    // x = 2^e · m with m in [√½, √2): subtracting √½'s bits borrows from the exponent
    // exactly when the mantissa is below √2.
    const I sqrt_half_bits = W::seti(0x3f3504f3);
    const I offset = W::subi(W::as_int(x), sqrt_half_bits);
    const F e = W::add(W::to_float(W::sra23(offset)), exponent_adjust);
    const F m = W::as_float(W::addi(W::andi(offset, W::seti(0x007fffff)), sqrt_half_bits));
    const F f = W::sub(m, W::set(1.0f));   // exact (Sterbenz)
    // ln(1 + f) = f − f²/2 + f³·P(f) on [√½ − 1, √2 − 1] (Cephes logf).
    F p = W::set(7.0376836292e-2f);
    p = W::fma(p, f, W::set(-1.1514610310e-1f));
    p = W::fma(p, f, W::set(1.1676998740e-1f));
    p = W::fma(p, f, W::set(-1.2420140846e-1f));
    p = W::fma(p, f, W::set(1.4249322787e-1f));
    p = W::fma(p, f, W::set(-1.6668057665e-1f));
    p = W::fma(p, f, W::set(2.0000714765e-1f));
    p = W::fma(p, f, W::set(-2.4999993993e-1f));
    p = W::fma(p, f, W::set(3.3333331174e-1f));
    const F f2 = W::mul(f, f);
    // e·ln2 in two parts (ln2_hi has 9 significant bits: e·ln2_hi is exact).
    F tail = W::fma(W::mul(f2, f), p, W::mul(e, W::set(-2.12194440e-4f)));
    tail = W::fnma(W::set(0.5f), f2, tail);
    return W::fma(e, W::set(0.693359375f), W::add(f, tail));
}

/// ln x for any x: subnormals scaled into the normal range, special values selected.
template <class W>
inline typename W::F log_wide(typename W::F x) {
    using F = typename W::F;
    const auto subnormal = W::less(x, W::set(1.17549435e-38f));
    const F scaled = W::select(subnormal, W::mul(x, W::set(8388608.0f)), x);   // · 2^23
    F result = log_normal<W>(scaled, W::select(subnormal, W::set(-23.0f), W::set(0.0f)));
    // x < 0 → NaN, ±0 → −inf, +inf and NaN → themselves.
    result = W::select(W::less(x, W::set(0.0f)), W::set(__builtin_nanf("")), result);
    result = W::select(W::equal(x, W::set(0.0f)), W::set(-__builtin_inff()), result);
    return W::select(W::not_less_equal(x, W::set(3.40282347e38f)), x, result);
}

}  // namespace detail

/// The lanes ln's narrow path does not cover: anything but positive normal numbers
/// (subnormal, zero, negative, inf, NaN).
template <class W>
inline typename W::M log_needs_wide(typename W::F x) {
    return W::or_mask(W::not_greater_equal(x, W::set(1.17549435e-38f)), W::greater(x, W::set(3.40282347e38f)));
}

/// ln x for a positive normal x.
template <class W>
inline typename W::F log_narrow(typename W::F x) {
    return detail::log_normal<W>(x, W::set(0.0f));
}

/// ln x, at most 1 float32 ULP from the exact value (vector_math.def).
template <class W>
inline typename W::F log(typename W::F x) {
    if (W::any(log_needs_wide<W>(x))) [[unlikely]]
        return detail::log_wide<W>(x);
    return log_narrow<W>(x);
}

}  // namespace fortu::vector_math::functions
