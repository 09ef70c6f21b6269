// runtime/image_compare.hpp — comparing an image fortu wrote with a reference image, through
// OpenImageIO's ImageBufAlgo::compare, and drawing where they differ. Used by `fortu golden`
// (style.md rule 9). The OpenImageIO code runs inside the image module (image_io.hpp).
#pragma once

#include "runtime/output_formats.hpp"

#include <string>
#include <vector>

namespace fortu {

/// What compare_images() found. `error` is set (and the rest meaningless) when either file
/// cannot be read or the two images do not have the same shape.
struct ImageComparison {
    std::string error;
    double max_error = 0.0;            ///< largest |expected − actual| over every channel
    unsigned long long failing = 0;    ///< pixels with some channel off by more than the tolerance
    unsigned long long pixels = 0;     ///< pixels compared (over every subimage)
    int worst_x = 0, worst_y = 0;      ///< the pixel with the largest error (column, row)
    int worst_subimage = 0;            ///< its subimage (an EXR part = a 3D slice)
    std::vector<float> expected;       ///< that pixel's channel values in the reference
    std::vector<float> actual;         ///< and in the new image
    std::vector<std::string> channels; ///< the channel names
    bool ok() const { return error.empty() && failing == 0; }
};

/// Compares every subimage of `actual_path` with `expected_path`, channel by channel, in the
/// files' own units (0..1 for 8-bit pictures, raw values for float EXR); a pixel fails when
/// a channel differs by more than `tolerance`. Non-finite values must match exactly (NaN
/// with NaN). Never throws.
ImageComparison compare_images(const std::string& expected_path, const std::string& actual_path,
                               double tolerance);

/// Writes |expected − actual| of `subimage` to `diff_path` (format by extension): a picture
/// is stretched so the largest difference is white, a float file keeps raw differences.
/// Returns an error text, or "" on success. Written atomically.
std::string write_diff_image(const std::string& expected_path, const std::string& actual_path,
                             int subimage, const std::string& diff_path);

/// The golden comparator of pictures and EXR files: compare_images() with the pixel
/// tolerance (pictures, in 8-bit levels) or the value tolerance (EXR), its verdict in words:
/// failing pixels, the largest error, the worst pixel with its world coordinates and both
/// values (pictures as 8-bit levels, EXR as `channel=value`).
OutputComparison compare_image_output(const ComparedOutput& compared);

/// write_diff_image() of the worst subimage of a failed compare_image_output().
std::string write_image_output_diff(const ComparedOutput& compared, const OutputComparison& comparison,
                                    const std::string& diff_path);

/// The module side of the two functions above (image_compare_oiio.cpp, in libfortu_image.so):
/// plain OpenImageIO, writing the difference straight to `file`.
ImageComparison oiio_compare_images(const std::string& expected_path, const std::string& actual_path,
                                    double tolerance);
std::string oiio_write_difference(const std::string& expected_path, const std::string& actual_path,
                                  int subimage, const std::string& file);

}  // namespace fortu
