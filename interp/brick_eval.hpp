// interp/brick_eval.hpp — a grid cut into bricks, and one brick's values evaluated on its own
// with interval pruning: the unit of out-of-core, resumable and distributed runs.
//
// Why: a 2048³ float64 grid is 64 GiB, but a 128³ brick is 16 MiB. Each brick runs the
// voxel engine's SSA tape shortened per sub-box (box_simplify.hpp, keep_values: the exact
// rules only) on the full grid's own coordinates (Grid::x_at ...), so its values equal the
// in-memory voxel run bit for bit. A sparse writer (the .vdb narrow band) may also say
// which values it does not need: sub-boxes whose interval lies beyond ±skip_beyond are
// not evaluated at all and get ±inf (their sign), which such a writer drops.
#pragma once

#include "interp/ir/ir.hpp"
#include "runtime/bricks.hpp"
#include "runtime/grid.hpp"

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

namespace fortu {

/// Counts of one brick's evaluation.
struct BrickStats {
    std::size_t evaluated_points = 0;  ///< points run through a tape
    std::size_t skipped_points = 0;    ///< points beyond skip_beyond, decided by intervals
    std::size_t operations = 0;        ///< tape operations, summed over evaluated points
};

/// Evaluates bricks of one model on one grid; one instance per thread (it owns its scratch).
class BrickEvaluator {
public:
    BrickEvaluator(const ir::Graph& graph, ir::NodeId root, const Grid& grid);
    ~BrickEvaluator();
    BrickEvaluator(const BrickEvaluator&) = delete;
    BrickEvaluator& operator=(const BrickEvaluator&) = delete;

    /// The brick's values in grid (image) order local to the box: index
    /// ((slice - lo[2]) * rows + (row - lo[1])) * cols + (col - lo[0]), into `values`
    /// (resized). With skip_beyond, values of sub-boxes the intervals put above it are
    /// +inf, below its negative -inf.
    BrickStats evaluate(const BrickBox& box, std::vector<double>& values,
                        std::optional<double> skip_beyond = std::nullopt);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Bytes one BrickEvaluator needs at most beside the brick's values (its tapes and lanes).
std::size_t brick_evaluator_bytes(const ir::Graph& graph, ir::NodeId root);

}  // namespace fortu
