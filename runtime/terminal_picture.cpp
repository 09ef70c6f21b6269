// runtime/terminal_picture.cpp — half-block and ASCII rendering of a slice; the colours and
// the contour come from render_slice(), so the terminal shows what the PNG would.
#include "runtime/terminal_picture.hpp"

#include "runtime/picture.hpp"

#include <cmath>
#include <fmt/format.h>
#include <span>

namespace fortu {

namespace {

/// Two pixels, upper over lower, as one half-block cell in 24-bit colour; `lower` null: none.
std::string half_block(Rgb8 upper, const Rgb8* lower) {
    std::string out = fmt::format("\x1b[38;2;{};{};{}m", upper.r, upper.g, upper.b);
    out += lower ? fmt::format("\x1b[48;2;{};{};{}m", lower->r, lower->g, lower->b) : std::string("\x1b[49m");
    return out + "\u2580";
}

}  // namespace

std::string terminal_surface_picture(const SurfaceImage& image, bool colour) {
    const std::vector<Rgb8> pixels = colour ? shade_surface(image) : std::vector<Rgb8>{};
    auto at = [&](int r, int c) { return static_cast<std::size_t>(r) * image.width + c; };
    std::string out;
    for (int r = 0; r < image.height; r += 2) {
        const bool has_lower = r + 1 < image.height;
        for (int c = 0; c < image.width; ++c) {
            if (colour) {
                out += half_block(pixels[at(r, c)], has_lower ? &pixels[at(r + 1, c)] : nullptr);
                continue;
            }
            const SurfaceImage::Hit hit = image.hit[at(r, c)];
            out += hit == SurfaceImage::Hit::Surface ? kAsciiSurface : hit == SurfaceImage::Hit::Cut ? kAsciiCut : kAsciiEmpty;
        }
        out += colour ? "\x1b[0m\n" : "\n";
    }
    return out;
}

std::string terminal_picture(const Field& field, int slice, bool colour, const OutputOptions& options) {
    const Grid& g = field.grid;
    const int cols = g.cols(), rows = g.rows();
    const std::size_t per_slice = static_cast<std::size_t>(cols) * rows;
    const std::span<const double> values(field.values.data() + per_slice * slice, per_slice);
    const std::vector<Rgb8> pixels = render_slice(field, slice, picture_colour_scale(values, options.picture.scale), options);
    auto at = [&](int r, int c) { return static_cast<std::size_t>(r) * cols + c; };

    std::string out;
    for (int r = 0; r < rows; r += 2) {
        const bool has_lower = r + 1 < rows;
        for (int c = 0; c < cols; ++c) {
            const Rgb8 up = pixels[at(r, c)];
            if (colour) {
                out += half_block(up, has_lower ? &pixels[at(r + 1, c)] : nullptr);
                continue;
            }
            const Rgb8 low = has_lower ? pixels[at(r + 1, c)] : up;
            const double v = values[at(r, c)];
            if (up == kContourColour || low == kContourColour) out += kAsciiContour;
            else if (!std::isfinite(v) || (has_lower && !std::isfinite(values[at(r + 1, c)]))) out += kAsciiInvalid;
            else out += v >= 0.0 ? kAsciiInside : kAsciiOutside;
        }
        out += colour ? "\x1b[0m\n" : "\n";
    }
    return out;
}

}  // namespace fortu
