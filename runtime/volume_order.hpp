// runtime/volume_order.hpp — a field's values in the order volume formats store them (VTK,
// NRRD, OpenVDB's index space): X fastest, then Y ascending, then Z ascending, with the
// origin at the box's smallest corner.
//
// Why: fortu's grids are in image order (row 0 = the largest Y, grid.hpp); a volume file
// is in world order, so only the rows of each slice come in reverse.
#pragma once

#include "runtime/field.hpp"

#include <array>

namespace fortu {

/// Calls visit(row_values, j, k) for every row of X values (cols() of them), j the Y index
/// from the smallest Y, k the Z index from the smallest Z, in storage order.
template <class Visit>
void for_each_volume_row(const Field& field, Visit&& visit) {
    const Grid& g = field.grid;
    for (int k = 0; k < g.slices(); ++k)
        for (int j = 0; j < g.rows(); ++j) visit(field.values.data() + g.index(0, g.rows() - 1 - j, k), j, k);
}

/// The smallest corner of the grid (its first node in volume order).
inline std::array<double, 3> volume_origin(const Grid& g) {
    return {g.x.min, g.y.nodes > 1 ? g.y.min : g.y.max, g.dims == 3 ? g.z.min : 0.0};
}

/// The spacing per axis; an axis with one node gets 1 (viewers divide by it).
inline std::array<double, 3> volume_spacing(const Grid& g) {
    auto step = [](const Axis& a) { return a.nodes > 1 ? a.step() : 1.0; };
    return {step(g.x), step(g.y), g.dims == 3 ? step(g.z) : 1.0};
}

}  // namespace fortu
