// runtime/picture_legend.cpp — layout and drawing of the legend (picture_legend.hpp).
#include "runtime/picture_legend.hpp"

#include "runtime/bitmap_font.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace fortu {
namespace {

constexpr Rgb8 kGround{255, 255, 255}, kInk{0, 0, 0}, kFrame{128, 128, 128};

std::string number(double v) { return v == 0 ? "0" : fmt::format("{:.3g}", v); }

// The bar row where `value` lies (the inverse of legend_bar_value), clamped to the bar.
int bar_row_of(const ColourScale& scale, double value, int height) {
    const double half = (height - 1) / 2.0;
    const double t = value >= 0 ? 1.0 - std::min(value / scale.inside, 1.0) : 1.0 + std::min(-value / scale.outside, 1.0);
    return static_cast<int>(std::lround(t * half));
}

}  // namespace

double legend_bar_value(const ColourScale& scale, int bar_row, int bar_height) {
    const double half = (bar_height - 1) / 2.0;
    const double t = bar_row / half;   // 0 top, 1 middle, 2 bottom
    return t <= 1.0 ? scale.inside * (1.0 - t) : -scale.outside * (t - 1.0);
}

std::vector<std::string> legend_caption(const Grid& grid, int slice, const PictureStyle& style) {
    const char h = style.axes.size() > 0 ? style.axes[0] : 'x', v = style.axes.size() > 1 ? style.axes[1] : 'y';
    std::vector<std::string> lines{fmt::format("{} [{}, {}]  {} [{}, {}]", h, number(grid.x.min), number(grid.x.max), v,
                                               number(grid.y.min), number(grid.y.max))};
    if (!style.plane.empty()) lines.push_back(style.plane);
    else if (grid.dims == 3 && grid.slices() > 1)
        lines.push_back(fmt::format("z = {} (slice {} of {})", number(grid.z_at(slice)), slice, grid.slices()));
    else if (grid.dims == 3) lines.push_back(fmt::format("z = {}", number(grid.z_at(slice))));
    return lines;
}

std::vector<std::string> legend_ticks(const ColourScale& scale) {
    return {number(scale.inside), number(scale.inside / 2), "0", number(-scale.outside / 2), number(-scale.outside)};
}

LegendLayout legend_layout(int cols, int rows, const std::vector<std::string>& ticks,
                           const std::vector<std::string>& caption) {
    LegendLayout l;
    l.text_scale = rows >= 480 || cols >= 640 ? 2 : 1;
    const int t = l.text_scale, margin = 6 * t, line = 10 * t;
    int label_width = 0, caption_width = 0;
    for (const std::string& s : ticks) label_width = std::max(label_width, text_width(s, t));
    for (const std::string& s : caption) caption_width = std::max(caption_width, text_width(s, t));
    l.bar_x = cols + margin;
    l.bar_y = margin;
    l.bar_width = 12 * t;
    l.bar_height = std::max(rows - 2 * margin, static_cast<int>(ticks.size()) * 2 * line) | 1;   // odd: 0 on a row
    l.label_x = l.bar_x + l.bar_width + 6 * t;
    l.caption_y = std::max(rows, l.bar_y + l.bar_height + margin) + margin;
    l.cols = std::max(l.label_x + label_width + margin, caption_width + 2 * margin);
    l.rows = l.caption_y + static_cast<int>(caption.size()) * line;
    return l;
}

Picture add_legend(const Picture& picture, const Grid& grid, int slice, const ColourScale& scale,
                   const std::vector<double>& levels, const PictureStyle& style) {
    const std::vector<std::string> ticks = legend_ticks(scale);
    const std::vector<std::string> caption = legend_caption(grid, slice, style);
    const LegendLayout l = legend_layout(picture.cols, picture.rows, ticks, caption);
    Picture out{l.cols, l.rows, std::vector<Rgb8>(static_cast<std::size_t>(l.cols) * l.rows, kGround)};
    auto put = [&out](int x, int y, Rgb8 colour) {
        if (x >= 0 && y >= 0 && x < out.cols && y < out.rows) out.pixels[static_cast<std::size_t>(y) * out.cols + x] = colour;
    };
    for (int r = 0; r < picture.rows; ++r)
        std::copy_n(picture.pixels.begin() + static_cast<std::ptrdiff_t>(r) * picture.cols, picture.cols,
                    out.pixels.begin() + static_cast<std::ptrdiff_t>(r) * out.cols);
    // The bar, its frame, and a line across it at each level (the zero in black).
    for (int r = 0; r < l.bar_height; ++r) {
        const Rgb8 colour = value_colour(legend_bar_value(scale, r, l.bar_height), scale);
        for (int c = 0; c < l.bar_width; ++c) put(l.bar_x + c, l.bar_y + r, colour);
    }
    for (int c = -1; c <= l.bar_width; ++c) {
        put(l.bar_x + c, l.bar_y - 1, kFrame);
        put(l.bar_x + c, l.bar_y + l.bar_height, kFrame);
    }
    for (int r = -1; r <= l.bar_height; ++r) {
        put(l.bar_x - 1, l.bar_y + r, kFrame);
        put(l.bar_x + l.bar_width, l.bar_y + r, kFrame);
    }
    for (double level : levels) {
        if (level > scale.inside || level < -scale.outside) continue;
        const int y = l.bar_y + bar_row_of(scale, level, l.bar_height);
        for (int c = 0; c < l.bar_width; ++c) put(l.bar_x + c, y, kLevelColour);
    }
    const int t = l.text_scale;
    for (std::size_t i = 0; i < ticks.size(); ++i) {
        const int y = l.bar_y + static_cast<int>(std::lround(i * (l.bar_height - 1) / double(ticks.size() - 1)));
        if (i == ticks.size() / 2)
            for (int c = 0; c < l.bar_width; ++c) put(l.bar_x + c, y, kContourColour);
        for (int c = 0; c < 4 * t; ++c)
            for (int w = 0; w < t; ++w) put(l.bar_x + l.bar_width + 1 + c, y + w, kInk);
        draw_text(ticks[i], l.label_x, y - kGlyphHeight * t / 2, t, [&](int x, int yy) { put(x, yy, kInk); });
    }
    for (std::size_t i = 0; i < caption.size(); ++i)
        draw_text(caption[i], 6 * t, l.caption_y + static_cast<int>(i) * 10 * t, t,
                  [&](int x, int y) { put(x, y, kInk); });
    return out;
}

}  // namespace fortu
