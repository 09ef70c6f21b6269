// runtime/field_difference.cpp — the value and sign differences of two fields (field_difference.hpp).
#include "runtime/field_difference.hpp"

#include <cassert>
#include <cmath>

namespace fortu {

FieldDifference field_difference(const Field& field, const Field& reference, std::size_t examples) {
    assert(field.values.size() == reference.values.size());
    FieldDifference d;
    double sum = 0.0;
    for (std::size_t p = 0; p < field.values.size(); ++p) {
        const double v = field.values[p], r = reference.values[p];
        if (std::isfinite(v) != std::isfinite(r)) ++d.invalid_in_one;
        if (!std::isfinite(v) || !std::isfinite(r)) continue;
        ++d.compared;
        const double diff = std::abs(v - r);
        if (diff > d.max) {
            d.max = diff;
            d.max_at = p;
        }
        sum += diff * diff;
        d.reference_magnitude = std::max(d.reference_magnitude, std::abs(r));
        if ((v > 0) != (r > 0) || (v < 0) != (r < 0)) {
            ++d.sign_differs;
            if (d.sign_examples.size() < examples) d.sign_examples.push_back(p);
        }
    }
    if (d.compared > 0) d.rms = std::sqrt(sum / double(d.compared));
    return d;
}

}  // namespace fortu
