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

    /// A field of `grid` with every value `fill`; a large one in transparent huge pages.
    static Field filled(const Grid& grid, double fill) {
        Field field{grid, {}};
        field.values.reserve(grid.points());
        advise_huge_pages(field.values.data(), grid.points() * sizeof(double));
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
