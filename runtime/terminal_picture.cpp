// runtime/terminal_picture.cpp — half-block and ASCII rendering of a slice; the colours and
// the contour come from render_slice(), so the terminal shows what the PNG would.
#include "runtime/terminal_picture.hpp"

#include "runtime/picture.hpp"

#include <cmath>
#include <fmt/format.h>
#include <span>

namespace fortu {

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
                out += fmt::format("\x1b[38;2;{};{};{}m", up.r, up.g, up.b);
                if (has_lower) {
                    const Rgb8 low = pixels[at(r + 1, c)];
                    out += fmt::format("\x1b[48;2;{};{};{}m", low.r, low.g, low.b);
                } else {
                    out += "\x1b[49m";
                }
                out += "\u2580";
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
