// cli/compare_report.hpp — `fortu run --compare ENGINE`: the text that says how far the run's
// result is from another engine's on the same grid (runtime/field_difference.hpp).
#pragma once

#include "runtime/field.hpp"

#include <string>

namespace fortu {

/// `LABEL against REFERENCE_LABEL on GRID = N nodes:` and indented lines: the largest
/// difference with where and both values, the RMS difference, the nodes whose sign differs
/// (the first few, and the count), and the nodes invalid in only one of them.
std::string compare_report(const Field& result, const std::string& label, const Field& reference,
                           const std::string& reference_label);

}  // namespace fortu
