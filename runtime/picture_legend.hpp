// runtime/picture_legend.hpp — the legend beside a picture (`--legend`): a colour bar with tick
// values on the picture's colour scale, its iso-levels marked, and a caption with the axes'
// ranges and a 3D slice's position, drawn with bitmap_font.hpp.
//
// Why: each side of the colour map saturates at its own value (picture.hpp), so without the
// numbers a reader cannot tell a 0.006 tooth from a 0.6 body, nor which slice a picture shows.
#pragma once

#include "runtime/grid.hpp"
#include "runtime/output_options.hpp"
#include "runtime/picture.hpp"

#include <string>
#include <vector>

namespace fortu {

/// A picture: cols x rows pixels in image order.
struct Picture {
    int cols = 0, rows = 0;
    std::vector<Rgb8> pixels;
    Rgb8 at(int col, int row) const { return pixels[static_cast<std::size_t>(row) * cols + col]; }
};

/// Where the legend puts things around a cols x rows picture (which stays at the top left).
struct LegendLayout {
    int cols = 0, rows = 0;                    ///< the whole image
    int text_scale = 1;                        ///< font pixels per glyph pixel (2 for large pictures)
    int bar_x = 0, bar_y = 0, bar_width = 0, bar_height = 0;   ///< the colour bar, right of the picture
    int label_x = 0;                           ///< the tick labels' left edge
    int caption_y = 0;                         ///< the caption's first line, below the picture
};

/// The colour bar runs from +scale.inside (top row) through 0 (middle) to −scale.outside
/// (bottom row), each half linear like the colour map's sides.
double legend_bar_value(const ColourScale& scale, int bar_row, int bar_height);

/// The caption lines: the axes' ranges (`x [-1, 1]  y [-1, 1]`), then for a 3D grid the
/// slice (`z = 0.25 (slice 8 of 17)`) or style.plane.
std::vector<std::string> legend_caption(const Grid& grid, int slice, const PictureStyle& style);

/// The tick labels, top to bottom: +inside, +inside/2, 0, −outside/2, −outside.
std::vector<std::string> legend_ticks(const ColourScale& scale);

LegendLayout legend_layout(int cols, int rows, const std::vector<std::string>& ticks,
                           const std::vector<std::string>& caption);

/// `picture` (of a slice of `grid`) with the legend around it on a white ground.
Picture add_legend(const Picture& picture, const Grid& grid, int slice, const ColourScale& scale,
                   const std::vector<double>& levels, const PictureStyle& style);

}  // namespace fortu
