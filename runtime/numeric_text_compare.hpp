// runtime/numeric_text_compare.hpp — comparing two texts fortu wrote (.csv, .svg) number by
// number, for golden tests: the words between the numbers must be identical, the numbers
// equal within the tolerance, so a last-digit rounding change is not a failure.
#pragma once

#include "runtime/output_formats.hpp"

namespace fortu {

/// Compares the reference text with the new output; a difference names the first line
/// whose words differ, or the line of the worst number with both lines quoted.
OutputComparison compare_numeric_text(const ComparedOutput& compared);

}  // namespace fortu
