// runtime/image_table.hpp — an image file read as a table of numbers (grey levels in [0, 1]),
// for height maps given as pictures (fv-method.md §5.2); OpenImageIO does the decoding.
#pragma once

#include <cstddef>
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

/// Reads any format OpenImageIO knows. On failure returns nullopt and says why in `error`; a
/// picture of more than `max_pixels` pixels is refused from its header, before decoding.
std::optional<ImageTable> read_image_table(const std::string& path, std::string& error,
                                           std::size_t max_pixels);

}  // namespace fortu
