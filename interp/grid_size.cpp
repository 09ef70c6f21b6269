// interp/grid_size.cpp — square cells from one --size number.
#include "interp/grid_size.hpp"

#include "interp/engine.hpp"

#include <algorithm>
#include <cmath>

namespace fortu {

std::array<AxisRange, 3> model_box(const Model& model, const std::array<std::optional<AxisRange>, 3>& domain) {
    std::array<AxisRange, 3> box;
    for (int a = 0; a < 3; ++a) {
        if (a < static_cast<int>(model.arguments.size()) && model.ranges[a]) box[a] = *model.ranges[a];
        if (domain[a]) box[a] = *domain[a];
    }
    return box;
}

void size_axes(std::array<AxisRange, 3>& box, std::array<int, 3>& nodes, const std::vector<int>& axes,
               const std::vector<int>& size) {
    if (size.empty() || axes.empty()) return;
    if (size.size() > 1) {
        for (std::size_t i = 0; i < axes.size(); ++i) nodes[axes[i]] = size[std::min(i, size.size() - 1)];
        return;
    }
    const int n = size[0];
    int longest = axes[0];
    for (int a : axes)
        if (box[a].max - box[a].min > box[longest].max - box[longest].min) longest = a;
    nodes[longest] = n;
    const double cell = n > 1 ? (box[longest].max - box[longest].min) / (n - 1) : 0.0;
    for (int a : axes) {
        if (a == longest) continue;
        if (n == 1) { nodes[a] = 1; continue; }
        const double extent = box[a].max - box[a].min;
        const int cells = std::max(1, static_cast<int>(std::ceil(extent / cell - 1e-9)));
        nodes[a] = cells + 1;
        const double centre = (box[a].min + box[a].max) / 2, half = cells * cell / 2;
        box[a] = AxisRange{centre - half, centre + half};
    }
}

Grid sized_grid(const Model& model, const std::vector<int>& size,
                const std::array<std::optional<AxisRange>, 3>& domain) {
    std::array<AxisRange, 3> box = model_box(model, domain);
    std::array<int, 3> nodes = grid_nodes(model, size);
    const int axis_count = model.arguments.size() == 1 ? 1 : model.dims();
    if (size.size() == 1 && axis_count > 1) {
        std::vector<int> axes;
        for (int a = 0; a < axis_count; ++a) axes.push_back(a);
        size_axes(box, nodes, axes, size);
    }
    std::array<std::optional<AxisRange>, 3> ranges;
    for (int a = 0; a < 3; ++a) ranges[a] = box[a];
    return model_grid(model, nodes, ranges);
}

}  // namespace fortu
