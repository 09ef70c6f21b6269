// interp/engine.hpp — what both engines share: which one, how to run it, and the entry
// points the command line calls (a whole grid, or one point with its gradient).
#pragma once

#include "interp/model.hpp"
#include "runtime/field.hpp"
#include "runtime/grid.hpp"

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace fortu {

enum class EngineKind { Classic, Voxel };

std::optional<EngineKind> parse_engine(const std::string& name);
const char* engine_name(EngineKind kind);

/// The voxel engine's number type: float64 (default: values identical to the classic
/// engine's) or float32 (twice the lanes per vector; see README "Performance" for the tolerance).
enum class Precision { Float64, Float32 };

struct EvalOptions {
    int threads = 0;                                   ///< 0: all cores
    Precision precision = Precision::Float64;          ///< voxel engine only
    std::function<void(std::size_t points)> progress;  ///< called as tiles/rows complete
    const std::atomic<bool>* cancel = nullptr;         ///< set to stop early (REPL Ctrl-C)
    /// Voxel engine: compute X-only sub-expressions once per column and those without X
    /// once per row (hoist.hpp). Off only to compare against the plain tape.
    bool hoist = true;
    /// Voxel engine: nodes whose values on this grid are already known (grid order, one per
    /// point); they are read instead of computed, and what only they use is not computed.
    std::vector<std::pair<ir::NodeId, const double*>> known;
    /// Voxel engine: nodes whose values are also written out (grid order, one per point),
    /// beside the root's. Incomplete if the evaluation was cancelled.
    std::vector<std::pair<ir::NodeId, double*>> keep;
};

/// Samples the model on every node of `grid` with the chosen engine. Both engines give
/// the same values (the same kernels in the same order; see architecture.md).
Field evaluate_grid(const Model& model, const Grid& grid, EngineKind engine,
                    const EvalOptions& options = {});
/// The same for any node of the model's graph (a sub-expression).
Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, EngineKind engine,
                    const EvalOptions& options = {});

struct PointValue {
    double value = 0.0;
    std::array<double, 3> gradient{};   ///< exact (forward-mode AD), d/dX, d/dY, d/dZ
};

/// The value and gradient at one point (coordinates beyond the model's arguments ignored).
PointValue evaluate_point(const Model& model, std::array<double, 3> point, EngineKind engine);

/// The grid over the model's box — per axis `domain[a]` if given, else the script's range
/// (ARGUMENT X(5), RECTANGLE), else [-1, 1] — with `nodes` per axis; a 2D model gets one
/// slice and a one-argument model one row.
Grid model_grid(const Model& model, std::array<int, 3> nodes,
                const std::array<std::optional<AxisRange>, 3>& domain = {});

/// Nodes per axis for a run: `size` (1 to 3 numbers, the last repeated), else RECTBMP, else
/// 256² (2D) or 64³ (3D).
std::array<int, 3> grid_nodes(const Model& model, const std::vector<int>& size);

/// Deepest recursion the classic engine accepts (its walk is recursive by definition).
inline constexpr int kClassicMaxDepth = 20000;

/// Length of the longest operand chain from the root (the classic engine's recursion depth).
int dag_depth(const ir::Graph& graph, ir::NodeId root);

}  // namespace fortu
