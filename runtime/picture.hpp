// runtime/picture.hpp — the function as a picture: a diverging colour map (inside warm, outside
// blue as in the papers' figures), the zero contour in black, invalid points in magenta;
// 8-bit RGB through OpenImageIO (architecture.md "Outputs a user expects").
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_options.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace fortu {

struct Rgb8 {
    std::uint8_t r = 0, g = 0, b = 0;
    friend bool operator==(const Rgb8&, const Rgb8&) = default;
};

/// Zero-contour pixels.
inline constexpr Rgb8 kContourColour{0, 0, 0};
/// Iso-lines other than zero (`--levels`): grey, so the zero contour stays the black one.
inline constexpr Rgb8 kLevelColour{110, 110, 110};
/// Invalid points (non-finite values, fortu-language.md §2): a colour no value maps to.
inline constexpr Rgb8 kInvalidColour{255, 0, 255};
/// Inside (value > 0): cream at the contour, deep orange at |value| ≥ scale.
inline constexpr Rgb8 kInsideNear{255, 243, 214}, kInsideFar{232, 117, 26};
/// Outside (value < 0): pale blue at the contour, deep blue at |value| ≥ scale.
inline constexpr Rgb8 kOutsideNear{234, 242, 255}, kOutsideFar{47, 95, 179};

/// The |value| at which each side of the colour map saturates. The two sides are scaled on
/// their own (like a two-slope norm) because R-function models are typically small inside and
/// large outside, and one common scale would leave the inside nearly flat.
struct ColourScale {
    double inside = 1.0;    ///< for values > 0
    double outside = 1.0;   ///< for values < 0 (a magnitude)
};

/// The colour scale of a set of values: on each side, the 99th percentile of |v| over the
/// finite values of that sign, so a few huge values (near a pole) do not wash out the picture.
/// A side with no values (or only zeros) borrows the other side's scale, else 1. Large inputs
/// are sampled (about a million values).
ColourScale colour_scale(std::span<const double> values);

/// The colour scale a picture uses for `values` under `choice`: Auto is colour_scale(); Symmetric
/// the 99th percentile of |v| over all finite non-zero values, on both sides; Fixed the given
/// ends (outside = −low, inside = high).
ColourScale picture_colour_scale(std::span<const double> values, const ScaleChoice& choice);

/// The iso-levels drawn besides zero: style.levels, or style.level_count per side at
/// k/count of that side's scale (k = 1..count, so the last is where the colour saturates),
/// inside first, ascending; zero is left out.
std::vector<double> picture_levels(const ColourScale& scale, const PictureStyle& style);

/// The colour of one value: the near colour blended towards the far one by min(|v|/scale, 1),
/// optionally darkened in `bands` stripes per scale unit; 0 counts as inside and a non-finite
/// value is kInvalidColour. (The contour is drawn by render_slice.)
Rgb8 value_colour(double value, const ColourScale& scale, int bands = 0);

/// The slice a picture of a 3D grid shows: `requested`, or the middle one for −1; 0 in 2D.
/// −1 if `requested` is out of range.
int picture_slice(const Grid& grid, int requested);

/// One slice drawn as rows()×cols() pixels in image order. A pixel is on the zero contour if
/// its value is 0, or if a 4-neighbour has the opposite sign and a magnitude at least as
/// large (so the line runs on the side nearer to the true zero, one pixel wide). The levels of
/// picture_levels(scale, options.picture) are drawn by the same rule on value − level, in
/// kLevelColour, under the zero contour. (The legend is added by write_picture.)
std::vector<Rgb8> render_slice(const Field& field, int slice, const ColourScale& scale,
                               const OutputOptions& options);

/// Writes 8-bit pixels (`channels` per pixel, image order) to `path` through OpenImageIO,
/// atomically; the format follows the extension. Throws OutputError.
void write_image_8bit(const std::string& path, int cols, int rows, int channels,
                      std::span<const std::uint8_t> pixels, const OutputOptions& options);

/// The picture of `field`: 2D, one file; 3D, the slice options.slice (middle by default), or
/// every slice if the target is a series (`slice_%03d.png`, numbered from 0 = smallest Z, all
/// slices on one colour scale). Throws OutputError.
void write_picture(const Field& field, const OutputTarget& target, const OutputOptions& options);

}  // namespace fortu
