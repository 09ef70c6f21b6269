// runtime/field_stats.hpp — summary numbers of a sampled field for `--stats` and `fortu eval`:
// range and mean over the finite values, and how many points are inside, on the boundary,
// outside, or invalid (fortu-language.md §2: invalid points are excluded from statistics).
#pragma once

#include "runtime/field.hpp"

#include <cstddef>
#include <limits>
#include <span>

namespace fortu {

struct FieldStats {
    std::size_t points = 0;     ///< all values
    std::size_t invalid = 0;    ///< non-finite values (NaN, ±inf)
    std::size_t positive = 0;   ///< finite values > 0: inside
    std::size_t zero = 0;       ///< exactly 0: on the boundary
    std::size_t negative = 0;   ///< finite values < 0: outside
    /// Over the finite values only; NaN if there are none.
    double min = std::numeric_limits<double>::quiet_NaN();
    double max = std::numeric_limits<double>::quiet_NaN();
    double mean = std::numeric_limits<double>::quiet_NaN();
};

/// The statistics of a set of values (the mean is summed with Neumaier compensation).
FieldStats field_stats(std::span<const double> values);

/// The statistics of a field's values.
inline FieldStats field_stats(const Field& field) { return field_stats(field.values); }

}  // namespace fortu
