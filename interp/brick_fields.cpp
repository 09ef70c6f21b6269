// interp/brick_fields.cpp — a brick's values and components (brick_fields.hpp): evaluated
// over the stencils' reach, components from the whole grid's stencil, own nodes cut out.
#include "interp/brick_fields.hpp"

#include <algorithm>

namespace fortu {

BrickFieldEvaluator::BrickFieldEvaluator(const ir::Graph& graph, ir::NodeId root, const Grid& grid, bool components)
    : values_(graph, root, grid) {
    if (components) stencil_.emplace(grid);
}

BrickStats BrickFieldEvaluator::evaluate(const BrickBox& box, BrickFields& out, std::optional<double> skip_beyond) {
    if (!stencil_) {
        out.components.clear();
        return values_.evaluate(box, out.values, skip_beyond);
    }
    const BrickBox reach = stencil_->reach(box);
    const BrickStats stats = values_.evaluate(reach, out.reach);
    const std::size_t points = box.points();
    out.values.resize(points);
    const int cols = box.extent()[0];
    for (int s = box.lo[2]; s <= box.hi[2]; ++s)
        for (int r = box.lo[1]; r <= box.hi[1]; ++r)
            std::copy_n(out.reach.data() + reach.local(box.lo[0], r, s), cols, out.values.data() + box.local(box.lo[0], r, s));
    out.components.resize(std::size_t(stencil_->components()) * points);
    double* n[5];
    for (int k = 0; k < stencil_->components(); ++k) n[k] = out.components.data() + k * points;
    stencil_->box(out.reach.data(), reach, box, n);
    return stats;
}

std::size_t brick_fields_bytes(const BrickLayout& layout, bool components) {
    const Grid& g = layout.grid;
    const int nodes[3] = {g.cols(), g.rows(), g.slices()};
    std::size_t own = 1, reach = 1;
    for (int a = 0; a < 3; ++a) {
        const std::size_t edge = std::size_t(std::min(layout.shape[a], nodes[a]));
        own *= edge;
        reach *= std::min(edge + 1, std::size_t(nodes[a]));
    }
    const std::size_t arrays = std::size_t(fv_component_count(g));
    return components ? 8 * (reach + own * (1 + arrays)) : 8 * own;
}

}  // namespace fortu
