// runtime/field_stats.cpp — one pass over the values.
#include "runtime/field_stats.hpp"

#include <algorithm>
#include <cmath>

namespace fortu {

FieldStats field_stats(std::span<const double> values) {
    FieldStats s;
    s.points = values.size();
    double sum = 0.0, compensation = 0.0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double v : values) {
        if (!std::isfinite(v)) {
            ++s.invalid;
            continue;
        }
        s.positive += v > 0.0;
        s.zero += v == 0.0;
        s.negative += v < 0.0;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        const double t = sum + v;
        compensation += std::abs(sum) >= std::abs(v) ? (sum - t) + v : (v - t) + sum;
        sum = t;
    }
    const std::size_t finite = s.points - s.invalid;
    if (finite > 0) {
        s.min = lo;
        s.max = hi;
        s.mean = (sum + compensation) / static_cast<double>(finite);
    }
    return s;
}

}  // namespace fortu
