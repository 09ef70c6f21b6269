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

/// Points per tile: 1024 (8 KiB per float64 slot; prospero.vm has ~160 live slots, 1.3 MiB,
/// but consecutive instructions mostly touch the few just written, still in L1); longer lane loops pay the
/// per-instruction dispatch less often — 1024 lanes ran prospero.vm 7% faster than 512 and
/// 16% faster than 256 in float32 (single thread, 1024², min of 5).
inline constexpr int kTileSize = 1024;

/// Grids narrower than this are evaluated in flat tiles, without hoisting (hoist.hpp): a
/// tile per row would leave most of each vector loop's length unused.
inline constexpr int kMinHoistColumns = 64;

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
