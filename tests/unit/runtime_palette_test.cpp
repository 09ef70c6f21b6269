// tests/unit/runtime_palette_test.cpp — palette encoding (fv-method.md §1.1 item 5) and its
// quantisation error on the dissertation's circle (§1.1 item 7).
#include "runtime/fv_model.hpp"
#include "runtime/palette.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace fortu;

TEST_CASE("palette codes: P−1 is the top code") {
    CHECK(palette_levels(Palette::Grey8) == 256);
    CHECK(palette_levels(Palette::Rgb24) == 16777216);
    CHECK(palette_encode(-1.0, Palette::Grey8) == 0);
    CHECK(palette_encode(1.0, Palette::Grey8) == 255);
    CHECK(palette_encode(0.0, Palette::Grey8) == 128);   // 127.5 rounds up
    CHECK(palette_encode(1.0, Palette::Rgb24) == 16777215);
    CHECK(palette_encode(-1.0, Palette::Rgb24) == 0);
    CHECK(palette_decode(0, Palette::Grey8) == -1.0);
    CHECK(palette_decode(255, Palette::Grey8) == 1.0);
    CHECK(palette_decode(16777215, Palette::Rgb24) == 1.0);
    CHECK(palette_encode(3.0, Palette::Grey8) == 255);
    CHECK(palette_encode(-3.0, Palette::Rgb24) == 0);
    CHECK(palette_encode(std::nan(""), Palette::Grey8) == 0);
}

TEST_CASE("palette round trips: every code decodes and re-encodes to itself") {
    for (std::uint32_t m = 0; m < 256; ++m) CHECK(palette_encode(palette_decode(m, Palette::Grey8), Palette::Grey8) == m);
    for (std::uint32_t m : {0u, 1u, 4095u, 8388607u, 8388608u, 16777214u, 16777215u})
        CHECK(palette_encode(palette_decode(m, Palette::Rgb24), Palette::Rgb24) == m);
    double worst8 = 0.0, worst24 = 0.0;
    for (int i = -1000; i <= 1000; ++i) {
        const double n = i / 1000.0;
        worst8 = std::max(worst8, std::abs(palette_decode(palette_encode(n, Palette::Grey8), Palette::Grey8) - n));
        worst24 = std::max(worst24, std::abs(palette_decode(palette_encode(n, Palette::Rgb24), Palette::Rgb24) - n));
    }
    CHECK(worst8 <= 1.0 / 255 + 1e-15);      // half a step of 2/(P−1)
    CHECK(worst24 <= 1.0 / 16777215 + 1e-15);
}

TEST_CASE("24-bit packing: R = M>>16, G = (M>>8)&255, B = M&255") {
    CHECK(rgb24_pack(0xABCDEF) == std::array<std::uint8_t, 3>{0xAB, 0xCD, 0xEF});
    CHECK(rgb24_unpack(0xAB, 0xCD, 0xEF) == 0xABCDEFu);
    CHECK(rgb24_unpack(255, 255, 255) == 16777215u);
    static_assert(rgb24_unpack(1, 2, 3) == (1u << 16 | 2u << 8 | 3u));
}

namespace {

// Worst error of the value recovered at every node from its palette-quantised components.
double recovery_error(Palette palette) {
    Field field;
    field.grid.x = {-1.0, 1.0, 60};
    field.grid.y = {-1.0, 1.0, 60};
    const Grid& g = field.grid;
    field.values.resize(g.points());
    for (int r = 0; r < g.rows(); ++r)
        for (int c = 0; c < g.cols(); ++c) {
            const double x = g.x_at(c), y = g.y_at(r);
            field.values[g.index(c, r)] = 0.4 - (x - 0.3) * (x - 0.3) - (y - 0.3) * (y - 0.3);
        }
    const FvModel model(field);
    double worst = 0.0;
    for (int r = 0; r < g.rows(); ++r)
        for (int c = 0; c < g.cols(); ++c) {
            const std::size_t i = g.index(c, r);
            std::array<double, 4> n{};
            for (int k = 1; k <= 4; ++k) n[k - 1] = palette_decode(palette_encode(model.n(k, i), palette), palette);
            worst = std::max(worst, std::abs(local_value(n, g.x_at(c), g.y_at(r)) - field.values[i]));
        }
    return worst;
}

}  // namespace

TEST_CASE("quantisation error of value recovery: ~6e-2 with P = 256, ~1e-6 with P = 2^24") {
    const double grey = recovery_error(Palette::Grey8);
    const double rgb = recovery_error(Palette::Rgb24);
    INFO("P = 256: " << grey << ", P = 2^24: " << rgb);
    CHECK(grey > 2e-2);
    CHECK(grey < 0.15);
    CHECK(rgb > 1e-7);
    CHECK(rgb < 5e-6);
}
