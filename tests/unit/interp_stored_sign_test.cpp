// tests/unit/interp_stored_sign_test.cpp — the sign renderer's stored signs (stored_sign.hpp):
// the hand-vectorised int8 row against the one-value rule, on every kind of float.
#include "interp/stored_sign.hpp"
#include "interp/sign_render.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using namespace fortu;

TEST_CASE("16- and 8-wide int8 sign rows equal the one-value rule for every kind of float, in every lane") {
    const float inf = std::numeric_limits<float>::infinity();
    const float kinds[] = {1.0f, -1.0f, 0.0f, -0.0f, inf, -inf, std::nanf(""), -std::nanf(""),
                           std::numeric_limits<float>::denorm_min(), -std::numeric_limits<float>::denorm_min(),
                           std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), 3e-30f, -7.5f};
    constexpr int kKinds = sizeof(kinds) / sizeof(kinds[0]);
    // Every kind in every lane, beside every other kind.
    for (int shift = 0; shift < kKinds; ++shift) {
        float row[16];
        for (int c = 0; c < 16; ++c) row[c] = kinds[(c * 5 + shift) % kKinds];
        int8_t got[16], got8[16], want[16];
        store_sign_row<16>(got, row, 16);
        store_sign_row<8>(got8, row, 8);
        store_sign_row<8>(got8 + 8, row + 8, 8);
        for (int c = 0; c < 16; ++c) want[c] = stored_sign_of<int8_t>(row[c]);
        for (int c = 0; c < 16; ++c) {
            INFO("lane " << c << " value " << row[c]);
            CHECK(got[c] == want[c]);
            CHECK(got8[c] == want[c]);
        }
    }
    // The codes themselves: ~sign, and NaN's code is ~kNaN.
    CHECK(stored_sign_of<int8_t>(2.5f) == SignVolume::code_of(1));
    CHECK(stored_sign_of<int8_t>(-0.0f) == SignVolume::code_of(0));
    CHECK(stored_sign_of<int8_t>(-inf) == SignVolume::code_of(-1));
    CHECK(stored_sign_of<int8_t>(std::nanf("")) == SignVolume::code_of(SignVolume::kNaN));
}
