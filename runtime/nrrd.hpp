// runtime/nrrd.hpp — a field as NRRD (.nrrd: a text header attached to raw little-endian
// float64 data), read by 3D Slicer, ParaView, ITK, teem, pynrrd: sizes, space origin and
// directions (the spacing), in volume order (volume_order.hpp).
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"

#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// The header, up to and including the blank line that ends it.
std::string nrrd_header(const Grid& grid);

/// Writes the .nrrd. Throws OutputError.
void write_nrrd(const Field& field, const OutputTarget& target, const OutputOptions& options);

/// Compares a reference .nrrd (as write_nrrd() writes it for the grid) with the field.
OutputComparison compare_nrrd(const ComparedOutput& compared);

}  // namespace fortu
