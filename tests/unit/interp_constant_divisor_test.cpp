// Which divisors the compiled tapes multiply by, and that the corrected reciprocal gives the
// quotient's bits: every float32 significand against a set of divisors of both kinds (the
// rule scales: x·2^k and c·2^k give the same bits, shifted), float64 by random sampling,
// and the ends of the range where the code uses it.
#include "interp/constant_divisor.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

using namespace fortu;

namespace {

template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

/// x in [1, 2) over every float32 significand whose corrected quotient by c differs from x / c.
int differing_significands(float c) {
    const ConstantDivisor<float> plan = plan_constant_divisor(c);
    int differing = 0;
    for (uint32_t significand = 0; significand < (1u << 23); ++significand) {
        const uint32_t bits = 0x3f800000u | significand;
        float x;
        std::memcpy(&x, &bits, 4);
        differing += !same_bits(corrected_quotient(x, c, plan.reciprocal), x / c);
    }
    return differing;
}

}  // namespace

TEST_CASE("constant divisors: powers of two by their reciprocal, others corrected where Markstein's bound holds") {
    CHECK(plan_constant_divisor(1.0f).kind == DivisorKind::exact_reciprocal);
    CHECK(plan_constant_divisor(0.5f).kind == DivisorKind::exact_reciprocal);
    CHECK(plan_constant_divisor(-16.0).kind == DivisorKind::exact_reciprocal);
    CHECK(plan_constant_divisor(-16.0).reciprocal == -0.0625);
    // 2^127's reciprocal is subnormal in float32, not in float64.
    CHECK(plan_constant_divisor(std::ldexp(1.0f, 127)).kind == DivisorKind::divide);
    CHECK(plan_constant_divisor(std::ldexp(1.0, 127)).kind == DivisorKind::exact_reciprocal);
    // bear.vm's divisors: |RN(1/c)·c − 1| ≤ 2^-25 for 0.9, 0.3 and 5.612245, exactly 2^-25
    // for 1.5 and 11; 1.68·2^-25 for 30.555555.
    for (float c : {0.9f, 0.3f, 5.612245f, 1.5f, 11.0f, -0.7f})
        CHECK(plan_constant_divisor(c).kind == DivisorKind::corrected_reciprocal);
    CHECK(plan_constant_divisor(30.555555f).kind == DivisorKind::divide);
    // In float64 0.9 is not (RN(1/0.9)·0.9 − 1 = 0.62 · 2^-53), 0.3 is.
    CHECK(plan_constant_divisor(0.9).kind == DivisorKind::divide);
    CHECK(plan_constant_divisor(0.3).kind == DivisorKind::corrected_reciprocal);
    // No constants the code could not divide by exactly in its range, nor zeros and the like.
    for (float c : {0.0f, -0.0f, INFINITY, NAN, std::ldexp(3.0f, -40), std::ldexp(3.0f, 40), 1e-40f})
        CHECK(plan_constant_divisor(c).kind == DivisorKind::divide);
}

TEST_CASE("the corrected reciprocal gives x / c bit for bit: every float32 significand") {
    for (float c : {0.9f, 1.5f, 11.0f, 0.15f, -5.612245f, 3.0f, 1.00000012f, 1.99999976f}) {
        CAPTURE(c);
        REQUIRE(plan_constant_divisor(c).kind == DivisorKind::corrected_reciprocal);
        CHECK(differing_significands(c) == 0);
    }
}

TEST_CASE("the corrected reciprocal gives x / c bit for bit over its whole range, float32 and float64") {
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> significand(1.0, 2.0);
    const auto check_range = [&]<class T>(T) {
        constexpr int kX = CorrectedRange<T>::kExponent, kC = CorrectedRange<T>::kDivisorExponent;
        std::uniform_int_distribution<int> x_exponent(-kX, kX - 1), c_exponent(-kC, kC - 1);
        int tested = 0, differing = 0;
        while (tested < 2'000'000) {
            const T c = std::ldexp(T(significand(random)), c_exponent(random)) * (random() % 2 ? 1 : -1);
            const ConstantDivisor<T> plan = plan_constant_divisor(c);
            if (plan.kind != DivisorKind::corrected_reciprocal) continue;
            for (int k = 0; k < 20; ++k, ++tested) {
                // The ends of the range (|x| = 2^kX is in it) as often as inside it.
                const int e = k % 4 == 0 ? -kX : k % 4 == 1 ? kX - 1 : x_exponent(random);
                const T x = (k == 5 ? std::ldexp(T(1), kX) : std::ldexp(T(significand(random)), e)) *
                            (random() % 2 ? 1 : -1);
                differing += !same_bits(corrected_quotient(x, c, plan.reciprocal), x / c);
            }
        }
        CHECK(differing == 0);
    };
    check_range(0.0f);
    check_range(0.0);
}
