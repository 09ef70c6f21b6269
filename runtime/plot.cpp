// runtime/plot.cpp — SVG line plots: data range → "nice" ticks (1-2-5 steps on linear axes,
// decades on log axes) → a plot area with grid lines, polylines with markers, and a legend.
#include "runtime/plot.hpp"

#include "runtime/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

namespace fortu {
namespace {

constexpr double kPlotWidth = 450, kMinPlotHeight = 380;
constexpr double kLeft = 80, kMinRight = 230, kTop = 40, kBottom = 60;
/// The legend: its sample line and gap (54 px), an upper bound on a character's width in the
/// 12 px sans-serif font (so a name is never cut at the picture's edge), and a line's height.
constexpr double kLegendLead = 54, kLegendCharWidth = 7.5, kLegendLine = 20;
constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                    "#e377c2", "#7f7f7f"};

std::string xml_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

/// One axis: its data range (in log10 units on a log axis) and its ticks.
struct Scale {
    bool log = false;
    double lo = 0, hi = 1;
    std::vector<double> ticks;   ///< in data units

    double to_unit(double v) const {   // 0..1 along the axis
        const double t = log ? std::log10(v) : v;
        return (t - lo) / (hi - lo);
    }
};

bool drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

/// Ticks 1-2-5 × 10^k covering [lo, hi], and the range widened to whole ticks.
Scale linear_scale(double lo, double hi) {
    Scale s;
    if (!(hi > lo)) { lo -= 1; hi += 1; }
    const double raw = (hi - lo) / 6;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * mag >= raw) { step = m * mag; break; }
    s.lo = std::floor(lo / step) * step;
    s.hi = std::ceil(hi / step) * step;
    for (double t = s.lo; t <= s.hi + step * 1e-9; t += step) s.ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
    return s;
}

/// Whole decades covering [lo, hi] (positive data); 2 and 5 between them on a short range.
Scale log_scale(double lo, double hi) {
    Scale s;
    s.log = true;
    s.lo = std::floor(std::log10(lo));
    s.hi = std::ceil(std::log10(hi));
    if (s.hi <= s.lo) s.hi = s.lo + 1;
    const bool fine = s.hi - s.lo <= 2;
    const int every = s.hi - s.lo > 8 ? 2 : 1;
    for (int e = int(s.lo); e <= int(s.hi); ++e) {
        if ((e - int(s.lo)) % every == 0) s.ticks.push_back(std::pow(10.0, e));
        if (fine && e < int(s.hi)) {
            s.ticks.push_back(2 * std::pow(10.0, e));
            s.ticks.push_back(5 * std::pow(10.0, e));
        }
    }
    std::sort(s.ticks.begin(), s.ticks.end());
    return s;
}

Scale make_scale(const Plot& plot, bool x_axis) {
    const bool log = x_axis ? plot.log_x : plot.log_y;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const PlotSeries& s : plot.series)
        for (auto [x, y] : s.points) {
            const double v = x_axis ? x : y;
            if (!drawable(x, plot.log_x) || !drawable(y, plot.log_y)) continue;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    if (!std::isfinite(lo)) { lo = log ? 1 : 0; hi = log ? 10 : 1; }
    return log ? log_scale(lo, hi) : linear_scale(lo, hi);
}

std::string tick_text(double v) {
    if (v == 0) return "0";
    const double a = std::abs(v);
    if (a >= 1e5 || a < 1e-3) return fmt::format("{:.0e}", v);
    return fmt::format("{:g}", v);
}

/// Displayed characters (UTF-8 continuation bytes take no width).
std::size_t shown_characters(const std::string& s) {
    std::size_t n = 0;
    for (unsigned char c : s) n += (c & 0xC0) != 0x80;
    return n;
}

}  // namespace

std::string render_plot_svg(const Plot& plot) {
    const Scale sx = make_scale(plot, true), sy = make_scale(plot, false);
    // The picture grows to hold the legend: as wide as its longest name, as tall as its lines.
    std::size_t longest = 0;
    for (const PlotSeries& s : plot.series) longest = std::max(longest, shown_characters(s.name));
    const double right = std::max(kMinRight, std::ceil(kLegendLead + kLegendCharWidth * double(longest) + 12));
    const double pw = kPlotWidth, ph = std::max(kMinPlotHeight, kLegendLine * double(plot.series.size()) + 10);
    const double width = kLeft + pw + right, height = kTop + ph + kBottom;
    auto px = [&](double x) { return kLeft + sx.to_unit(x) * pw; };
    auto py = [&](double y) { return kTop + (1 - sy.to_unit(y)) * ph; };

    std::string svg = fmt::format(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
        "font-family=\"sans-serif\" font-size=\"12\">\n"
        "<rect width=\"{0}\" height=\"{1}\" fill=\"white\"/>\n"
        "<text x=\"{2}\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">{3}</text>\n",
        width, height, kLeft + pw / 2, xml_escape(plot.title));
    // Grid lines and tick labels.
    for (double t : sx.ticks) {
        const double x = px(t);
        svg += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1}\" x2=\"{0:.1f}\" y2=\"{2}\" stroke=\"#ddd\"/>\n"
                           "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4}</text>\n",
                           x, kTop, kTop + ph, kTop + ph + 16, tick_text(t));
    }
    for (double t : sy.ticks) {
        const double y = py(t);
        svg += fmt::format("<line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" stroke=\"#ddd\"/>\n"
                           "<text x=\"{3}\" y=\"{4:.1f}\" text-anchor=\"end\">{5}</text>\n",
                           kLeft, y, kLeft + pw, kLeft - 6, y + 4, tick_text(t));
    }
    svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>\n",
                       kLeft, kTop, pw, ph);
    svg += fmt::format("<text class=\"x-label\" x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}{}</text>\n",
                       kLeft + pw / 2, height - 18, xml_escape(plot.x_label), plot.log_x ? " (log scale)" : "");
    svg += fmt::format("<text class=\"y-label\" x=\"{0}\" y=\"{1}\" text-anchor=\"middle\" "
                       "transform=\"rotate(-90 {0} {1})\">{2}{3}</text>\n",
                       22, kTop + ph / 2, xml_escape(plot.y_label), plot.log_y ? " (log scale)" : "");
    // Series, then the legend to the right of the plot area.
    for (std::size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        const std::size_t index = s.colour >= 0 ? std::size_t(s.colour) : i;
        const char* colour = kColours[index % std::size(kColours)];
        std::string points;
        std::string markers;
        for (auto [x, y] : s.points) {
            if (!drawable(x, plot.log_x) || !drawable(y, plot.log_y)) continue;
            points += fmt::format("{}{:.1f},{:.1f}", points.empty() ? "" : " ", px(x), py(y));
            if (!s.dashed)
                markers += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"/>\n", px(x), py(y), colour);
        }
        svg += fmt::format("<g class=\"series\" data-name=\"{}\">\n", xml_escape(s.name));
        if (!points.empty())
            svg += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"2\"{} points=\"{}\"/>\n", colour,
                               s.dashed ? " stroke-dasharray=\"6 4\"" : "", points);
        svg += markers + "</g>\n";
        const double ly = kTop + 10 + kLegendLine * double(i);
        svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"{3}\" stroke-width=\"2\"{4}/>\n"
                           "<text class=\"legend\" x=\"{5}\" y=\"{6}\">{7}</text>\n",
                           kLeft + pw + 12, ly, kLeft + pw + 36, colour, s.dashed ? " stroke-dasharray=\"6 4\"" : "",
                           kLeft + pw + 42, ly + 4, xml_escape(s.name));
    }
    svg += "</svg>\n";
    return svg;
}

void write_plot_svg(const Plot& plot, const std::string& path) {
    const std::string svg = render_plot_svg(plot);
    write_file_atomically(path, [&](OutputFile& f) { f.write(svg); });
}

}  // namespace fortu
