// cli/run_grid.cpp — choosing the grid of a run (see run_grid.hpp).
#include "cli/run_grid.hpp"

#include "cli/model_setup.hpp"

#include "grammar/diagnostic.hpp"
#include "interp/domain_auto.hpp"
#include "interp/engine.hpp"
#include "interp/grid_size.hpp"
#include "interp/ir_print.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_path.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <iostream>

namespace fortu {
namespace {

const char* const kAxisNames[3] = {"x", "y", "z"};

/// The default plane of a slice: 256 nodes along its longer side.
constexpr int kDefaultPlaneNodes = 256;
constexpr int kDefaultViewPixels = 512;

std::array<std::optional<AxisRange>, 3> run_domain(const Model& model, const CliOptions& o) {
    std::array<std::optional<AxisRange>, 3> domain = o.domain;
    if (o.domain_auto) {
        auto found = find_domain_auto(model);
        if (const std::string* problem = std::get_if<std::string>(&found)) throw UsageError(*problem);
        const auto& box = std::get<std::array<AxisRange, 3>>(found);
        for (int a = 0; a < static_cast<int>(model.arguments.size()); ++a)
            if (!domain[a]) domain[a] = box[a];
        return domain;
    }
    if (!model.domain_note.empty()) {
        bool overridden = true;
        for (int a = 0; a < static_cast<int>(model.arguments.size()); ++a) overridden &= domain[a].has_value();
        if (!overridden) std::cerr << model.domain_note;
    }
    return domain;
}

}  // namespace

SliceChoice parse_slice_choice(const std::string& text) {
    SliceChoice s;
    auto bad = [&] {
        return UsageError(fmt::format("--slice: '{}' is not a slice (use z=0.3, x=-1.2, y=0, or a z slice number K)",
                                      text));
    };
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos) {
        int v = 0;
        auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || v < 0) throw bad();
        s.index = v;
        return s;
    }
    const std::string axis = text.substr(0, eq), value = text.substr(eq + 1);
    if (axis == "x" || axis == "X") s.axis = 0;
    else if (axis == "y" || axis == "Y") s.axis = 1;
    else if (axis == "z" || axis == "Z") s.axis = 2;
    else throw bad();
    auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), s.at);
    if (value.empty() || ec != std::errc() || ptr != value.data() + value.size() || !std::isfinite(s.at)) throw bad();
    return s;
}

std::array<AxisRange, 3> run_box(const Model& model, const CliOptions& o) {
    return model_box(model, run_domain(model, o));
}

Grid run_grid(const Model& model, const CliOptions& o) {
    if (model.dims() == 2 && o.size.size() == 3)
        throw UsageError(fmt::format("--size: the model has {} argument(s); give N or WxH", model.arguments.size()));
    if (o.slice && model.dims() != 3)
        throw UsageError("--slice: the model has 2 arguments; slices are planes of 3D models");
    const bool view = wants_shaded_view(model, o);
    if (model.dims() == 3 && o.size.size() == 2 && !o.slice && !view)
        throw UsageError(fmt::format("--size: '{}x{}' has 2 numbers but the model has 3 arguments; give N, WxHxD, "
                                     "or a plane with --slice", o.size[0], o.size[1]));
    const std::array<std::optional<AxisRange>, 3> domain = run_domain(model, o);
    if (!o.slice || view) {
        Grid grid = sized_grid(model, view ? std::vector<int>{} : o.size, domain);
        check_grid_points(grid);
        return grid;
    }
    const SliceChoice& s = *o.slice;
    if (s.index) {
        if (o.size.size() == 2)
            throw UsageError("--slice K numbers a z slice of the cube --size gives; give N or WxHxD, or --slice z=V");
        Grid grid = sized_grid(model, o.size, domain);
        if (*s.index >= grid.slices())
            throw UsageError(fmt::format("--slice: {} is outside 0..{}", *s.index, grid.slices() - 1));
        grid.z.min = grid.z.max = grid.z_at(*s.index);
        grid.z.nodes = 1;
        check_grid_points(grid);
        return grid;
    }
    std::array<AxisRange, 3> box = model_box(model, domain);
    const AxisRange& r = box[s.axis];
    if (s.at < r.min || s.at > r.max)
        throw UsageError(fmt::format("--slice: {}={} is outside the domain's {} [{}, {}]", kAxisNames[s.axis], s.at,
                                     model.arguments[s.axis], r.min, r.max));
    std::array<int, 3> nodes{1, 1, 1};
    std::vector<int> plane;
    for (int a = 0; a < 3; ++a)
        if (a != s.axis) plane.push_back(a);
    std::vector<int> size = o.size;
    if (size.size() == 3) size = {size[plane[0]], size[plane[1]]};
    if (size.empty()) size = {kDefaultPlaneNodes};
    size_axes(box, nodes, plane, size);
    box[s.axis] = AxisRange{s.at, s.at};
    nodes[s.axis] = 1;
    std::array<std::optional<AxisRange>, 3> ranges;
    for (int a = 0; a < 3; ++a) ranges[a] = box[a];
    Grid grid = model_grid(model, nodes, ranges);
    check_grid_points(grid);
    return grid;
}

bool wants_shaded_view(const Model& model, const CliOptions& o) {
    if (model.dims() != 3 || o.output.empty() || o.slice || is_file_series(o.output)) return false;
    const OutputFormat* format = output_format_for(o.output);
    return format && format->kind == OutputKind::Picture;
}

std::array<int, 2> view_size(const CliOptions& o) {
    if (o.size.empty()) return {kDefaultViewPixels, kDefaultViewPixels};
    if (o.size.size() == 3) throw UsageError("--size: a shaded view is a picture; give N or WxH");
    return {o.size[0], o.size.size() == 2 ? o.size[1] : o.size[0]};
}

int z_slice_number(const Grid& cube, const SliceChoice& slice) {
    if (slice.index) {
        if (*slice.index >= cube.slices())
            throw UsageError(fmt::format("--slice: {} is outside 0..{}", *slice.index, cube.slices() - 1));
        return *slice.index;
    }
    if (slice.axis != 2) throw UsageError("--slice: only z slices here (--slice z=V or K)");
    if (slice.at < cube.z.min || slice.at > cube.z.max)
        throw UsageError(fmt::format("--slice: z={} is outside the domain's z [{}, {}]", slice.at, cube.z.min, cube.z.max));
    return cube.z.nodes > 1 ? static_cast<int>(std::lround((slice.at - cube.z.min) / cube.z.step())) : 0;
}

Field plane_picture(const Field& field) {
    const Grid& g = field.grid;
    if (g.dims != 3 || g.slices() < 2 || (g.cols() != 1 && g.rows() != 1)) return field;
    const bool x_plane = g.cols() == 1;
    Field out;
    out.grid.dims = 2;
    out.grid.x = x_plane ? Axis{g.y.min, g.y.max, g.rows()} : g.x;
    out.grid.y = g.z;
    out.grid.z = Axis{0, 0, 1};
    const int cols = out.grid.cols(), rows = out.grid.rows();
    out.values.resize(std::size_t(cols) * rows);
    for (int row = 0; row < rows; ++row) {
        const int slice = rows - 1 - row;   // row 0 is the largest Z
        for (int col = 0; col < cols; ++col) {
            // A y plane keeps X as it is; an x plane's Y runs down the grid's rows (row 0 = largest Y).
            const std::size_t from = x_plane ? g.index(0, g.rows() - 1 - col, slice) : g.index(col, 0, slice);
            out.values[std::size_t(row) * cols + col] = field.values[from];
        }
    }
    return out;
}

}  // namespace fortu
