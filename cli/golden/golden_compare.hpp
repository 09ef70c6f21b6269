// cli/golden_compare.hpp — comparing what a model produced with a golden test's reference
// files, numerically with a tolerance: raw values (.npy), and text with numbers in it (.csv,
// .svg). Images go through runtime/image_compare.hpp (OpenImageIO).
#pragma once

#include "runtime/field.hpp"

#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// The verdict of one comparison: `difference` is empty when the files agree, else a
/// one-paragraph account of what differed (counts, the worst place, both values).
struct FileComparison {
    std::string difference;
    bool ok() const { return difference.empty(); }
};

/// Compares `field` with the .npy file at `expected_path` (float64 or float32, the shape of
/// the grid): every value within `tolerance`, NaN matching NaN and infinities matching
/// exactly. A file that is not a readable .npy of that shape is a difference that says so.
FileComparison compare_npy(const std::string& expected_path, const Field& field, double tolerance);

/// The values of a .npy reference of `grid`'s shape, or nullopt if it is not one.
std::optional<std::vector<double>> read_npy_values(const std::string& path, const Grid& grid);

/// Compares two texts (a .csv or .svg fortu wrote) number by number: the text between the
/// numbers must be identical, the numbers equal within `tolerance`.
FileComparison compare_numeric_text(const std::string& expected_path, const std::string& actual_path,
                                    double tolerance);

}  // namespace fortu
