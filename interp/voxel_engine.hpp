// interp/voxel_engine.hpp — iterative functional-voxel composition (the papers' method).
//
// Why: every sub-expression is computed once per grid point and R-operations are composed
// on the stored values of their operands, never by re-evaluating their definitions, so the
// cost is linear in nodes and points (architecture.md "voxel"). The DAG runs as a tape
// (tape.hpp) over tiles of points, one tile per worker at a time: memory is
// slots × tile, independent of the grid size.
#pragma once

#include "interp/engine.hpp"
#include "interp/tape.hpp"

namespace fortu {

/// Points per tile: 512 (4 KiB per float64 slot; prospero.vm has ~160 live slots, 640 KiB,
/// inside the 1 MiB L2); longer lane loops pay the per-instruction dispatch less often.
inline constexpr int kTileSize = 512;

void voxel_evaluate_grid(const ir::Graph& graph, ir::NodeId root, Field& field, const EvalOptions& options);

/// Evaluates one node's expression at single points, value and exact gradient; the tape is
/// compiled once, so repeated calls (Newton iterations, probes) cost one tape run each.
class PointEvaluator {
public:
    PointEvaluator(const ir::Graph& graph, ir::NodeId root);
    PointValue operator()(std::array<double, 3> point) const;

private:
    Tape tape_;
};

}  // namespace fortu
