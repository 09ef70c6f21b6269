// tests/unit/runtime_plot_test.cpp — the SVG plot writer: a complete document with the axis
// labels, the legend, one group per series, log ticks in decades, undrawable points left out,
// text escaped, and the file written atomically.
#include "runtime/plot.hpp"
#include "test_support.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace fortu;

namespace {

int count(const std::string& text, const std::string& what) {
    int n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
    return n;
}

Plot two_series(bool log_y) {
    Plot p;
    p.title = "E3 & friends";
    p.x_label = "steps";
    p.y_label = "wall time (s)";
    p.log_y = log_y;
    PlotSeries a("classic");
    a.points = {{1, 1}, {2, 10}, {3, 100}};
    PlotSeries b("voxel fit", true);
    b.points = {{1, 2}, {2, 3}, {3, 4}};
    p.series = {a, b};
    return p;
}

}  // namespace

TEST_CASE("render_plot_svg: a whole document with labels, legend and series") {
    const std::string svg = render_plot_svg(two_series(true));
    CHECK(svg.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"", 0) == 0);
    CHECK(svg.substr(svg.size() - 7) == "</svg>\n");
    CHECK(count(svg, "<svg ") == 1);
    CHECK(svg.find(">E3 &amp; friends</text>") != std::string::npos);
    CHECK(svg.find("<text class=\"x-label\"") != std::string::npos);
    CHECK(svg.find(">steps</text>") != std::string::npos);
    CHECK(svg.find(">wall time (s) (log scale)</text>") != std::string::npos);
    CHECK(svg.find("<text class=\"legend\" x=\"572\" y=\"54\">classic</text>") != std::string::npos);
    CHECK(svg.find("<text class=\"legend\" x=\"572\" y=\"74\">voxel fit</text>") != std::string::npos);
    CHECK(count(svg, "<g class=\"series\"") == 2);
    CHECK(count(svg, "<polyline") == 2);
    CHECK(count(svg, "stroke-dasharray") == 2);   // the dashed series and its legend line
    CHECK(count(svg, "<circle") == 3);            // markers only on measured series
    // Log axis 1..100: decades with 2 and 5 between them.
    for (const char* tick : {">1</text>", ">2</text>", ">5</text>", ">10</text>", ">20</text>", ">50</text>", ">100</text>"})
        CHECK(svg.find(tick) != std::string::npos);
    // Opening and closing tags balance.
    CHECK(count(svg, "<g ") == count(svg, "</g>"));
    CHECK(count(svg, "<text") == count(svg, "</text>"));
}

TEST_CASE("render_plot_svg: a fit can share its data's colour") {
    Plot p = two_series(false);
    p.series[1].colour = 0;
    const std::string svg = render_plot_svg(p);
    CHECK(count(svg, "stroke=\"#1f77b4\"") == 4);   // both polylines and both legend lines
    CHECK(count(svg, "#d62728") == 0);
}

TEST_CASE("render_plot_svg: points a log axis cannot show are left out") {
    Plot p = two_series(true);
    p.series[0].points = {{1, 0}, {2, -1}, {3, 1e-3}, {4, std::nan("")}};
    const std::string svg = render_plot_svg(p);
    const auto start = svg.find("data-name=\"classic\"");
    REQUIRE(start != std::string::npos);
    const std::string group = svg.substr(start, svg.find("</g>", start) - start);
    CHECK(count(group, "<circle") == 1);
    CHECK(count(group, "<polyline") == 1);
}

TEST_CASE("render_plot_svg: an empty plot still has its axes and labels") {
    Plot p;
    p.x_label = "grid points";
    p.y_label = "wall time (s)";
    const std::string svg = render_plot_svg(p);
    CHECK(count(svg, "<g class=\"series\"") == 0);
    CHECK(svg.find(">grid points</text>") != std::string::npos);
    CHECK(svg.find(">wall time (s)</text>") != std::string::npos);
    CHECK(svg.substr(svg.size() - 7) == "</svg>\n");
}

TEST_CASE("render_plot_svg: linear ticks in 1-2-5 steps") {
    Plot p;
    PlotSeries s("line");
    s.points = {{0, 0}, {10, 1}};
    p.series = {s};
    const std::string svg = render_plot_svg(p);
    for (const char* tick : {">0</text>", ">2</text>", ">4</text>", ">10</text>", ">0.2</text>", ">1</text>"})
        CHECK(svg.find(tick) != std::string::npos);
}

TEST_CASE("write_plot_svg writes exactly the rendered document") {
    const fortu::test::ScratchDir dir;
    const Plot p = two_series(false);
    write_plot_svg(p, dir / "p.svg");
    CHECK(dir.read("p.svg") == render_plot_svg(p));
    CHECK_THROWS(write_plot_svg(p, dir / "missing/p.svg"));
}
