// runtime/plot.hpp — a small SVG line-plot writer: several series of (x, y) points, labelled
// axes with units, linear or log scales, a legend. Written by fortu itself so `fortu bench`
// produces its figures without Python or a plotting library.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace fortu {

/// One curve of a plot: its legend text and its points (drawn in the given order).
struct PlotSeries {
    explicit PlotSeries(std::string name_in = {}, bool dashed_in = false)
        : name(std::move(name_in)), dashed(dashed_in) {}
    std::string name;
    std::vector<std::pair<double, double>> points;
    bool dashed = false;   ///< a fitted line rather than measurements (no markers)
    int colour = -1;       ///< palette index, so a fit can share its data's colour; -1: by position
};

struct Plot {
    std::string title;
    std::string x_label;   ///< with its unit, e.g. "grid points"
    std::string y_label;   ///< with its unit, e.g. "wall time (s)"
    bool log_x = false;
    bool log_y = false;
    std::vector<PlotSeries> series;
};

/// The plot as a standalone SVG document. Points that cannot be drawn (non-finite, or ≤ 0
/// on a log axis) are left out; an empty plot still has its axes, labels and legend.
std::string render_plot_svg(const Plot& plot);

/// render_plot_svg() written atomically to `path`; throws OutputError on failure.
void write_plot_svg(const Plot& plot, const std::string& path);

}  // namespace fortu
