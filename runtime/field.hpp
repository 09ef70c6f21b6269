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

    std::size_t invalid_count() const {
        std::size_t n = 0;
        for (double v : values) n += !std::isfinite(v);
        return n;
    }
};

}  // namespace fortu
