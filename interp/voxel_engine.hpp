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

/// The instruction set the voxel engine's lane loops run with on this CPU: "AVX-512" (the
/// x86-64-v4 copy the loader picked), "AVX2" or "SSE2" (the build's -march).
const char* lane_loop_isa();

/// Grids narrower than this are evaluated in flat tiles, without hoisting (hoist.hpp): a
/// tile per row would leave most of each vector loop's length unused.
inline constexpr int kMinHoistColumns = 64;

/// The voxel engine's own options.
struct VoxelOptions {
    /// float32: twice the lanes per vector; values within 1e-5 of the field (README "Performance").
    Precision precision = Precision::Float64;
    /// Compute X-only sub-expressions once per column, those without X once per row and, in
    /// 3D, those of X and Y (X and Z) alone once per XY (XZ) plane (hoist.hpp). Off only to
    /// compare against the plain tape (--no-hoist).
    bool hoist = true;
    /// Run large passes as machine code compiled from the tape (tape_jit.hpp; the same
    /// values). Off only to compare against the lane loops (--no-jit).
    bool compile = true;
    /// Passes of fewer lane operations (instructions × points) than this run in the lane
    /// loops: compiling costs about a microsecond per instruction, which these would not
    /// save back.
    double compile_above_lane_operations = 1e8;
};

/// Points are computed in double for either precision (PointEvaluator); known and kept
/// node values (NodeValues) are supported.
class VoxelEngine final : public Engine {
public:
    explicit VoxelEngine(VoxelOptions options = {}) : options_(options) {}
    std::string_view name() const override;
    std::string_view summary() const override;
    EngineCapabilities capabilities() const override;
    std::unique_ptr<Engine> tuned(const EngineSettings& settings) const override;
    Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                        const NodeValues& reuse) const override;
    PointValue evaluate_point(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point) const override;

private:
    VoxelOptions options_;
};

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
