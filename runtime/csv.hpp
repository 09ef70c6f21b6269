// runtime/csv.hpp — the raw values as CSV, one line per grid node: `x,y,value` (2D) or
// `x,y,z,value` (3D), for spreadsheets and scripts (architecture.md "Outputs a user expects").
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"

#include <string>

namespace fortu {

/// Writes the header line, then one line per node in image order (slice, row, col), every
/// number with 17 significant digits (`%.17g`, which round-trips a double) and non-finite
/// values as `nan`, `inf`, `-inf`. Throws OutputError.
void write_csv(const Field& field, const OutputTarget& target, const OutputOptions& options = {});

}  // namespace fortu
