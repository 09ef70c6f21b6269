// runtime/terminal_picture.hpp — a Field slice drawn as text for a terminal (`fortu repl`'s
// :show): truecolour half blocks, two pixels per character cell, in the same colours and with
// the same zero contour as the picture files (picture.hpp); plain ASCII when colour is off.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_options.hpp"
#include "runtime/surface_picture.hpp"

#include <string>

namespace fortu {

/// Characters of the ASCII picture: one per cell, a cell being two pixels stacked.
inline constexpr char kAsciiInside = '#', kAsciiOutside = '.', kAsciiContour = '*', kAsciiInvalid = '?';

/// Draws slice `slice` of `field` (see picture_slice) as ceil(rows / 2) lines of cols()
/// cells. Colour: each cell is U+2580 (upper half block) with the upper pixel as foreground
/// and the lower one as background (24-bit SGR), reset at the end of each line; an odd last
/// row leaves the lower half in the terminal's own background. ASCII: a cell shows the
/// contour if either pixel is on it, else invalid if either is invalid, else inside if the
/// upper pixel's value is ≥ 0. Every line ends in '\n'.
std::string terminal_picture(const Field& field, int slice, bool colour, const OutputOptions& options = {});

/// Characters of the ASCII shaded view: the solid's surface, a face cut by the domain, nothing.
inline constexpr char kAsciiSurface = '#', kAsciiCut = '+', kAsciiEmpty = '.';

/// A shaded view of a solid (shade_surface's colours) drawn as terminal_picture draws a slice:
/// half blocks in colour; in ASCII a cell shows the upper pixel's hit (surface, cut, nothing).
std::string terminal_surface_picture(const SurfaceImage& image, bool colour);

}  // namespace fortu
