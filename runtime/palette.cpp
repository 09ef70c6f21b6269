// runtime/palette.cpp — palette encoding and decoding of FV components (fv-method.md §1.1
// item 5).
#include "runtime/palette.hpp"

#include <algorithm>
#include <cmath>

namespace fortu {

std::uint32_t palette_encode(double n, Palette palette) {
    if (std::isnan(n)) return 0;
    const double top = palette_levels(palette) - 1.0;
    const double m = std::round(top * (1.0 + std::clamp(n, -1.0, 1.0)) / 2.0);
    return static_cast<std::uint32_t>(std::clamp(m, 0.0, top));
}

double palette_decode(std::uint32_t m, Palette palette) {
    const double top = palette_levels(palette) - 1.0;
    return 2.0 * m / top - 1.0;
}

}  // namespace fortu
