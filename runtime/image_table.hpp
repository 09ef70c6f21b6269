// runtime/image_table.hpp — an image file read as a table of numbers (grey levels in [0, 1]),
// for height maps given as pictures (fv-method.md §5.2); OpenImageIO does the decoding.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// A picture as numbers: `values[row * width + col]`, row 0 the top of the picture.
struct ImageTable {
    int width = 0;
    int height = 0;
    std::vector<double> values;   ///< the mean of the colour channels (alpha ignored), 0..1
};

/// Reads any format OpenImageIO knows. On failure returns nullopt and says why in `error`.
std::optional<ImageTable> read_image_table(const std::string& path, std::string& error);

}  // namespace fortu
