// runtime/palette.hpp — the papers' palette encoding of FV components into M-image codes
// (fv-method.md §1.1 item 5): P = 256 grey levels or P = 2^24 RGB colours. An export format
// only; fortu keeps components in double internally (§1.1 item 7).
#pragma once

#include <array>
#include <cstdint>

namespace fortu {

/// The two palettes of the sources: 8-bit grey (P = 256) and 24-bit RGB (P = 2^24).
enum class Palette { Grey8, Rgb24 };

/// P, the number of codes of a palette: 256 or 16 777 216.
constexpr std::uint32_t palette_levels(Palette palette) {
    return palette == Palette::Grey8 ? 256u : 1u << 24;
}

/// M = round((P−1)(1+n)/2). The sources write P(1+n)/2; P−1 is the top code so that n = 1
/// does not overflow (fv-method.md §1.1 item 5). n outside [−1, 1] is clamped; NaN (an
/// invalid node, which the palette cannot represent) encodes as 0.
std::uint32_t palette_encode(double n, Palette palette);

/// n = 2M/(P−1) − 1, the inverse of palette_encode (LRFM eq. 26 with P−1 as the top code).
double palette_decode(std::uint32_t m, Palette palette);

/// A 24-bit code as R, G, B bytes: R = M>>16, G = (M>>8)&255, B = M&255 (the sources do not
/// give the channel order; this is fortu's choice).
constexpr std::array<std::uint8_t, 3> rgb24_pack(std::uint32_t m) {
    return {static_cast<std::uint8_t>(m >> 16 & 255u), static_cast<std::uint8_t>(m >> 8 & 255u),
            static_cast<std::uint8_t>(m & 255u)};
}

/// The inverse of rgb24_pack.
constexpr std::uint32_t rgb24_unpack(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return std::uint32_t{r} << 16 | std::uint32_t{g} << 8 | std::uint32_t{b};
}

}  // namespace fortu
