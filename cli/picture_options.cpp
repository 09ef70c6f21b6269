// cli/picture_options.cpp — parsing --scale and --levels, and the legend's plane words.
#include "cli/picture_options.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <optional>

namespace fortu {
namespace {

std::optional<double> finite_number(const std::string& text) {
    double v = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
    return v;
}

std::string number(double v) { return fmt::format("{:.4g}", v); }

}  // namespace

ScaleChoice parse_scale_choice(const std::string& text) {
    if (text == "auto") return {};
    if (text == "symmetric") return {ScaleChoice::Mode::Symmetric};
    const std::vector<std::string> ends = split_value(text, ':');
    std::optional<double> low, high;
    if (ends.size() == 2) {
        low = finite_number(ends[0]);
        high = finite_number(ends[1]);
    }
    if (!low || !high)
        throw UsageError(fmt::format("--scale: '{}' is not auto, symmetric or A:B (numbers, e.g. -0.5:0.1)", text));
    const ScaleChoice fixed{ScaleChoice::Mode::Fixed, low.value(), high.value()};
    if (!(fixed.low < 0 && fixed.high > 0))
        throw UsageError(fmt::format("--scale: in '{}' A must be below 0 and B above 0 (the colours part at 0)", text));
    return fixed;
}

void parse_levels(const std::string& text, PictureStyle& style) {
    if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
        int count = 0;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), count);
        if (ec != std::errc() || ptr != text.data() + text.size() || count < 1 || count > 100)
            throw UsageError(fmt::format("--levels: '{}' levels per side is not from 1 to 100", text));
        style.level_count = count;
        style.levels.clear();
        return;
    }
    std::vector<double> levels;
    for (const std::string& part : split_value(text, ',')) {
        const std::optional<double> v = finite_number(part);
        if (!v)
            throw UsageError(fmt::format("--levels: '{}' is not a number in '{}' (use N, or values such as "
                                         "-0.1,0.05,0.2)", part, text));
        levels.push_back(*v);
    }
    if (levels.size() > 100)
        throw UsageError(fmt::format("--levels: {} values; at most 100", levels.size()));
    style.levels = std::move(levels);
    style.level_count = 0;
}

void add_picture_style_options(OptionTable& t, PictureStyle& style) {
    t.option("--scale", "auto|symmetric|A:B", "the colours' range: auto (each sign saturates at its own\n"
                                             "99th percentile of |value|), symmetric (one for both signs),\n"
                                             "or A:B, deep blue at A < 0 and deep orange at B > 0",
             [&style](const std::string& v) { style.scale = parse_scale_choice(v); });
    t.option("--levels", "N|V1,V2,...", "grey iso-lines besides the black zero contour: N per sign,\n"
                                       "evenly spaced up to where the colour saturates, or at the\n"
                                       "values given (one value with a point: 2.0)",
             [&style](const std::string& v) { parse_levels(v, style); });
    t.flag("--legend", "add a colour bar with its values (and the levels), the axes'\n"
                       "ranges and a 3D slice's position to the picture",
           [&style] { style.legend = true; });
}

PictureStyle plane_picture_style(const Field& field, PictureStyle style) {
    const Grid& g = field.grid;
    if (g.dims != 3 || g.slices() < 2) return style;
    if (g.cols() == 1) {
        style.axes = "yz";
        style.plane = fmt::format("x = {}", number(g.x.min));
    } else if (g.rows() == 1) {
        style.axes = "xz";
        style.plane = fmt::format("y = {}", number(g.y.min));
    }
    return style;
}

}  // namespace fortu
