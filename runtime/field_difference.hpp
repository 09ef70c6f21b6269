// runtime/field_difference.hpp — how far one sampled field is from a reference on the same
// grid: the largest and the RMS difference of the values, and the nodes whose sign differs
// (what `fortu run --compare` reports: the fv engine's error against exact evaluation).
#pragma once

#include "runtime/field.hpp"

#include <cstddef>
#include <vector>

namespace fortu {

struct FieldDifference {
    std::size_t compared = 0;        ///< nodes where both values are finite
    std::size_t invalid_in_one = 0;  ///< nodes finite in exactly one of the two
    double max = 0.0;                ///< largest |value − reference| over the compared nodes
    std::size_t max_at = 0;          ///< its node (image order)
    double rms = 0.0;                ///< root mean square of value − reference over the compared nodes
    double reference_magnitude = 0.0; ///< largest |reference| over the compared nodes
    std::size_t sign_differs = 0;    ///< compared nodes whose signs (−, 0, +) differ
    std::vector<std::size_t> sign_examples;   ///< the first few of them, in image order
};

/// Compares `field` with `reference` (the same grid); keeps up to `examples` sign examples.
FieldDifference field_difference(const Field& field, const Field& reference, std::size_t examples = 5);

}  // namespace fortu
