// runtime/npy.hpp — the raw values as a NumPy .npy file (format version 1.0, written by hand:
// no dependency), shape = grid, NaN/inf kept at invalid points (architecture.md "Outputs a
// user expects").
#pragma once

#include "runtime/field.hpp"

#include <string>

namespace fortu {

/// The complete .npy v1.0 header for the grid: magic `\x93NUMPY`, version 1.0, the
/// little-endian header length, then the dict `{'descr': '<f8', 'fortran_order': False,
/// 'shape': (rows, cols), }` (3D: (slices, rows, cols); `<f4` for float32) padded with spaces
/// and a final newline to a multiple of 64 bytes, as NumPy writes it.
std::string npy_header(const Grid& grid, bool float32);

/// Writes the values in image order (C order: slice, row, col), little-endian float64 or
/// float32. Throws OutputError.
void write_npy(const Field& field, const std::string& path, bool float32 = false);

}  // namespace fortu
