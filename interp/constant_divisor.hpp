// interp/constant_divisor.hpp — how compiled tapes divide by a constant: by multiplying,
// where that gives the quotient's own bits.
//
// Why: a division costs more than anything else the compiled tapes run. On Zen 4 a second
// vdivps beside each of bear.vm's 40 divisions per point made its 128³ float32 field 26%
// slower, while three more multiply-adds beside each cost nothing measurable: the divider,
// not the multiply-add units, is what the field waits for. 39 of bear.vm's 40 divisors are
// constants.
//
// Two exact replacements, chosen per divisor when the tape is compiled:
// - c = ±2^k with 1/c a normal number: x / c and x · (1/c) are the same real number, so
//   they round alike for every x (zeros, infinities, NaN, subnormal results, overflow).
// - Other c whose reciprocal y = RN(1/c) has |y·c − 1| ≤ 2^-(p+1) (p the precision's
//   significand bits; about seven constants in ten): q0 = RN(x·y) is then within one ulp of
//   x/c, and by Markstein's theorem (IBM J. Res. Dev. 34(1), 1990: y within half an ulp of
//   1/c, q0 within one ulp of x/c) the residual r = x − q0·c is exact in one fused
//   multiply-add and RN(q0 + r·y) = RN(x/c). The theorem needs no overflow or underflow on
//   the way, so it holds for |x| in the range below (and for NaN); a chunk with another lane
//   (zero among them: the zero residual's sign could flip a zero quotient's) divides instead.
// Divisors read per row (uniforms) can change after compiling: they are divided by.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace fortu {

enum class DivisorKind : uint8_t { divide, exact_reciprocal, corrected_reciprocal };

template <class T>
struct ConstantDivisor {
    DivisorKind kind = DivisorKind::divide;
    T reciprocal = T(0);
};

/// Where the corrected reciprocal is exact: |x| in [2^-kExponent, 2^kExponent] and |c| in
/// [2^-kDivisorExponent, 2^kDivisorExponent] (the quotient, reciprocal and residual then
/// stay far from overflow and from the subnormals).
template <class T>
struct CorrectedRange;
template <>
struct CorrectedRange<float> {
    static constexpr int kExponent = 64, kDivisorExponent = 32;
};
template <>
struct CorrectedRange<double> {
    static constexpr int kExponent = 400, kDivisorExponent = 200;
};

template <class T>
ConstantDivisor<T> plan_constant_divisor(T c) {
    constexpr int kBits = std::numeric_limits<T>::digits;
    if (!std::isnormal(c)) return {};
    const T reciprocal = T(1) / c;
    int exponent = 0;
    if (std::frexp(c, &exponent) == T(c < 0 ? -0.5 : 0.5) && std::isnormal(reciprocal))
        return {DivisorKind::exact_reciprocal, reciprocal};
    const T magnitude = std::fabs(c);
    constexpr int kRange = CorrectedRange<T>::kDivisorExponent;
    if (magnitude < std::ldexp(T(1), -kRange) || magnitude > std::ldexp(T(1), kRange)) return {};
    // y·c − 1, exact: in double for float32; for float64 in one fused multiply-add, since
    // y·c is within 2^-53 of 1 and a multiple of 2^-105.
    const double error = sizeof(T) == 4 ? std::fabs(double(reciprocal) * double(c) - 1.0)
                                        : std::fabs(std::fma(double(reciprocal), double(c), -1.0));
    if (error <= std::ldexp(1.0, -(kBits + 1))) return {DivisorKind::corrected_reciprocal, reciprocal};
    return {};
}

/// The corrected quotient as the compiled code computes it, one value of x in the range (for tests).
template <class T>
T corrected_quotient(T x, T c, T reciprocal) {
    const T q0 = x * reciprocal;
    return std::fma(-std::fma(q0, c, -x), reciprocal, q0);   // q0 − (q0·c − x)·y
}

}  // namespace fortu
