// runtime/field.hpp — a model sampled on a grid: one double per grid node.
// Non-finite values are "invalid points" (spec §2): kept as NaN/inf, counted, drawn in
// their own colour, excluded from statistics.
#pragma once

#include "runtime/grid.hpp"
#include "runtime/zeroed_pages.hpp"

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
    /// `threads` fault its pages in first, each a share of them in one call: on a virtual
    /// machine a page's first write traps to the kernel, and the fill alone was a serial
    /// tenth of a two-thread bear.vm 128³ field (docs/performance.md).
    static Field filled(const Grid& grid, double fill, int threads = 1) {
        Field field{grid, {}};
        field.values.reserve(grid.points());
        populate_whole_pages(field.values.data(), grid.points() * sizeof(double), threads);
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
