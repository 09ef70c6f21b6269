// interp/point_list.hpp — a model evaluated at arbitrary points (not a grid): the voxel
// engine's tape and lane kernel over tiles of points whose coordinates a caller supplies.
//
// Why: the Python module evaluates numpy arrays of any shape, where the points need not lie
// on a grid; walking the same tape with the same kernel keeps the values bit for bit equal
// to the engines' (and to `fortu eval`), and the tape is compiled once per model, so one
// point costs one tape run.
#pragma once

#include "interp/engine.hpp"
#include "interp/tape.hpp"

#include <array>
#include <cstddef>
#include <functional>

namespace fortu {

class PointListEvaluator {
public:
    PointListEvaluator(const ir::Graph& graph, ir::NodeId root);

    /// The value at one point (coordinates beyond the model's arguments ignored).
    double value(std::array<double, 3> point) const;

    /// Fills the coordinates of points [first, first + count): x[i], y[i], z[i] for the i-th.
    using Coordinates = std::function<void(std::size_t first, int count, double* x, double* y, double* z)>;
    /// The values of `points` points into out[0..points), tiles of up to kTileSize points
    /// shared among options.threads threads; stops early when options.cancel is set (then
    /// `out` is incomplete). `coordinates` is called from the worker threads.
    void values(std::size_t points, const Coordinates& coordinates, double* out, const EvalOptions& options) const;

private:
    Tape tape_;
};

}  // namespace fortu
