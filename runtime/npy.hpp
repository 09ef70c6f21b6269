// runtime/npy.hpp — the raw values as a NumPy .npy file (format version 1.0, written by hand:
// no dependency), shape = grid, NaN/inf kept at invalid points (architecture.md "Outputs a
// user expects"); and read back, value by value, for golden tests.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"

#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// The complete .npy v1.0 header for the grid: magic `\x93NUMPY`, version 1.0, the
/// little-endian header length, then the dict `{'descr': '<f8', 'fortran_order': False,
/// 'shape': (rows, cols), }` (3D: (slices, rows, cols); `<f4` for float32) padded with spaces
/// and a final newline to a multiple of 64 bytes, as NumPy writes it.
std::string npy_header(const Grid& grid, bool float32);

/// Writes the values in image order (C order: slice, row, col), little-endian float64 or
/// float32 (options.npy_float32). Throws OutputError.
void write_npy(const Field& field, const OutputTarget& target, const OutputOptions& options);

/// The values of a .npy file of `grid`'s shape as write_npy() writes it (v1.0, little-endian
/// f8/f4, C order), or nullopt if it is not one.
std::optional<std::vector<double>> read_npy_values(const std::string& path, const Grid& grid);

/// Compares the reference .npy with the field the new output was written from, value by
/// value (value_compare.hpp); a file that is not a readable .npy of the grid's shape is a
/// difference that says so.
OutputComparison compare_npy(const ComparedOutput& compared);

/// |reference − new| at every node drawn as a picture (equal nodes cream, the largest
/// differences deep orange), when the reference is readable; "" or an error text.
std::string write_npy_diff(const ComparedOutput& compared, const OutputComparison& comparison,
                           const std::string& diff_path);

}  // namespace fortu
