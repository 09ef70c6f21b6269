// interp/hoist.hpp — which sub-expressions the voxel engine computes per grid column, per
// grid row or (3D) per plane instead of per point.
//
// Why: on a grid, a sub-expression of X alone has only `cols` distinct values and one
// without X has only one value per row (rows × slices in all), yet a plain tape computes
// both at every point. In CSG-style models they are common — prospero.vm spends 35% of its
// operations on terms like (x - c)^2 and (y - c)^2 — so the engine computes them once per
// column or row, and the per-point tape reads them: column values as lane arrays, row
// values as immediates. In 3D, a sub-expression of X and Y alone has cols × rows values,
// the same in every slice (and one of X and Z alone the same in every row): bear.vm's body
// parts are mostly such terms, so they are computed once per plane and read as lane arrays
// too. Values are bit-identical, since each node is still computed by the same kernel from
// the same operand values.
#pragma once

#include "interp/ir/ir.hpp"

#include <cstddef>
#include <vector>

namespace fortu {

/// Which kinds of hoisting a plan may use: false where the values would not fit in memory
/// (or, for planes, on a 2D grid, where X and Y is every point).
struct HoistKinds {
    bool columns = true;     ///< X only: one value per column
    bool rows = true;        ///< no X (Y, Z, Y and Z): one value per row
    bool xy_planes = false;  ///< X and Y, no Z: one value per (column, row), for every slice
    bool xz_planes = false;  ///< X and Z, no Y: one value per (column, slice), for every row
};

struct HoistPlan {
    std::vector<ir::NodeId> column_nodes;    ///< X-only nodes the per-point tape reads
    std::vector<ir::NodeId> row_nodes;       ///< nodes without X (of Y, Z) the per-point tape reads
    std::vector<ir::NodeId> xy_plane_nodes;  ///< nodes of X and Y (no Z) the per-point tape reads
    std::vector<ir::NodeId> xz_plane_nodes;  ///< nodes of X and Z (no Y) the per-point tape reads
    std::size_t hoisted_operations = 0;      ///< operations taken out of the per-point tape
};

/// The plan for a tape computing `outputs` with `inputs` supplied (never hoisted, nor
/// looked through: their values are per point). Outputs are never hoisted themselves.
HoistPlan plan_hoisting(const ir::Graph& graph, const std::vector<ir::NodeId>& outputs,
                        const std::vector<ir::NodeId>& inputs, HoistKinds kinds = {});

}  // namespace fortu
