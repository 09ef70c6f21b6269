// runtime/exr.hpp — the FV model as one float OpenEXR file: the function value and the
// unquantised components n1..n4 (3D: n1..n5) as channels (fv-method.md §1; architecture.md
// "Outputs a user expects"). Serves both `-o out.exr` and `--mimages out.exr`.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"

#include <string>
#include <vector>

namespace fortu {

/// The channel names of the EXR of a grid: value, n1..n4 (2D) or value, n1..n5 (3D).
std::vector<std::string> exr_channel_names(const Grid& grid);

/// Writes `field` and its FV model as 32-bit float channels exr_channel_names(), NaN at
/// invalid points. 3D: one subimage (EXR part) per z slice, from the smallest Z, named
/// `z0000`, `z0001`, … with the float attribute `fortu:z`; a series target (`vol_%03d.exr`)
/// writes one single-part file per slice instead. Every file carries the string attribute
/// `fortu:domain` = `x0:x1,y0:y1[,z0:z1]`. The FV model is computed slice by slice, so memory
/// stays one slice of floats. Throws OutputError.
void write_exr(const Field& field, const OutputTarget& target, const OutputOptions& options = {});

}  // namespace fortu
