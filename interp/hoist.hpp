// interp/hoist.hpp — which sub-expressions the voxel engine computes per grid column or
// per grid row instead of per point.
//
// Why: on a grid, a sub-expression of X alone has only `cols` distinct values and one
// without X has only one value per row (rows × slices in all), yet a plain tape computes
// both at every point. In CSG-style models they are common — prospero.vm spends 35% of its
// operations on terms like (x - c)^2 and (y - c)^2 — so the engine computes them once per
// column or row, and the per-point tape reads them: column values as lane arrays, row
// values as immediates. Values are bit-identical, since each node is still computed by the
// same kernel from the same operand values.
#pragma once

#include "interp/ir/ir.hpp"

#include <cstddef>
#include <vector>

namespace fortu {

struct HoistPlan {
    std::vector<ir::NodeId> column_nodes;  ///< X-only nodes the per-point tape reads
    std::vector<ir::NodeId> row_nodes;     ///< nodes without X (of Y, Z) the per-point tape reads
    std::size_t hoisted_operations = 0;    ///< operations taken out of the per-point tape
};

/// The plan for a tape computing `outputs` with `inputs` supplied (never hoisted, nor
/// looked through: their values are per point). Outputs are never hoisted themselves.
/// `columns`/`rows` false: nothing is hoisted to columns/rows (their values would not fit).
HoistPlan plan_hoisting(const ir::Graph& graph, const std::vector<ir::NodeId>& outputs,
                        const std::vector<ir::NodeId>& inputs, bool columns = true, bool rows = true);

}  // namespace fortu
