// interp/sign_render.hpp — interval-pruned rendering of a model's sign (inside, boundary,
// outside, invalid) on a grid: a quadtree (2D) / octree (3D) over the grid's nodes.
//
// Why: a sign image or a contour does not need every value. Each box of the grid is
// evaluated once with interval arithmetic (interval.hpp); a box whose range excludes 0 gets
// one sign without touching its points; otherwise the tape is simplified for the box and
// its sub-boxes (box_simplify.hpp, performance-notes.md ideas 4-7): a min/max whose one
// operand wins over the whole box becomes that operand, and a node whose value matters only
// through its sign (its users are R-operations, min, max, neg) collapses by
// sign(a &α b) = sign(min(a, b)), sign(a |α b) = sign(max(a, b)) and becomes ±1 where its
// own sign is decided. The tapes are the voxel engine's (tape.hpp), run by its lane kernel.
#pragma once

#include "interp/engine.hpp"
#include "interp/ir/ir.hpp"
#include "runtime/field.hpp"
#include "runtime/field_stats.hpp"
#include "runtime/grid.hpp"
#include "runtime/zeroed_pages.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fortu {

/// Statistics of one pruned render (for --stats and tests).
struct SignRenderStats {
    std::size_t boxes = 0;          ///< boxes evaluated with intervals
    std::size_t decided_points = 0; ///< points whose sign came from a box's interval
    std::size_t leaf_points = 0;    ///< points evaluated one by one (on a simplified tape)
    std::size_t leaf_operations = 0;///< tape operations run per point, summed over leaf points
    std::size_t float64_leaves = 0; ///< leaf boxes run in float64 (the others in float32 within a proven bound)
};

/// The sign of the model at every grid node: 1 inside, 0 on the boundary, -1 outside, NaN
/// where the value is not a number (±inf keeps its sign). Equals the sign of the full
/// evaluation (float64) point for point, with one exception: where an R-operand is below
/// the other's rounding error (2^-53 of it, e.g. a line through a grid node, whose value
/// there is a residue ~1e-15), the full R-formula rounds the result to exactly 0 and the
/// pruned renderer gives that operand's sign, as sign(a & b) = sign(min(a, b)) says.
Field sign_render(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options = {},
                  SignRenderStats* stats = nullptr);

/// The signs of a grid kept as one int8 per node (1, 0, -1, kNaN), 8 times less memory than
/// a Field: how `fortu run --sign-only` keeps its signs (256³: 16 MiB, not 128 MiB, of which
/// only the pages the render writes are faulted in), expanded to float64 only when a values file is
/// written. Stored bit-inverted (`codes[i] = ~sign`), so outside (−1), the background of
/// most volumes, is a zero byte: fresh pages are outside without a pass writing them
/// (zeroed_pages.hpp).
struct SignVolume {
    static constexpr int8_t kNaN = -128;
    Grid grid;
    std::vector<int8_t, ZeroedPageAllocator<int8_t>> codes;   ///< grid.points() codes (~sign) in image order

    static constexpr int8_t code_of(int8_t sign) { return static_cast<int8_t>(~sign); }
    int8_t sign(std::size_t i) const { return static_cast<int8_t>(~codes[i]); }  ///< 1, 0, -1 or kNaN
    Field expanded() const;      ///< as float64 values (NaN for kNaN)
    FieldStats stats() const;    ///< equals field_stats(expanded())
};

/// sign_render into a SignVolume: the same signs, point for point.
SignVolume sign_render_volume(const ir::Graph& graph, ir::NodeId root, const Grid& grid,
                              const EvalOptions& options = {}, SignRenderStats* stats = nullptr);

/// sign_render as an engine (`--engine sign`, alias `--sign-only`): grids only, signs only.
class SignEngine final : public Engine {
public:
    std::string_view name() const override { return "sign"; }
    std::string_view summary() const override {
        return "only the sign (1, 0, -1, NaN): interval-pruned quadtree/octree";
    }
    EngineCapabilities capabilities() const override { return {.sign_only = true}; }
    std::unique_ptr<Engine> tuned(const EngineSettings&) const override { return std::make_unique<SignEngine>(); }
    Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                        const NodeValues& reuse) const override;
};

}  // namespace fortu
