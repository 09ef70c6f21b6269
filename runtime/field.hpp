// runtime/field.hpp — a model sampled on a grid: one double per grid node.
// Non-finite values are "invalid points" (spec §2): kept as NaN/inf, counted, drawn in
// their own colour, excluded from statistics.
#pragma once

#include "runtime/grid.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

namespace fortu {

struct Field {
    Grid grid;
    std::vector<double> values;   ///< grid.points() values in image order

    /// A field of `grid` with every value `fill`. In ordinary pages: asked for 2 MiB pages, a
    /// 256³ field (134 MB) filled in 14 ms when the kernel had them free, but in 190–260 ms
    /// when another process had just freed its memory (the kernel then compacts memory to
    /// make them), against 53–58 ms in 4 KiB pages either way (docs/performance.md).
    static Field filled(const Grid& grid, double fill) {
        Field field{grid, {}};
        field.values.assign(grid.points(), fill);
        return field;
    }

    std::size_t invalid_count() const {
        std::size_t n = 0;
        for (double v : values) n += !std::isfinite(v);
        return n;
    }
};

}  // namespace fortu
