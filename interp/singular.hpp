// interp/singular.hpp — singular (corner) points of an R-function model (fv-method.md §5.1).
//
// Why: a corner of an R-function model is where two boundaries produced by an R-operation
// meet. For p = φ op ψ the criterion is K = φ² + ψ² = 0, and for a whole model
// K = ∏ K_i over its R-operations with the extra condition R = 0 (a zero of K outside the
// final region is not on the model's boundary). K_i = 0 exactly where both operands of
// R-operation i vanish, so the points are found per operation: seeds on a grid where φ_i
// and ψ_i both change sign, refined by Newton's method on (φ_i, ψ_i) = 0 with exact
// gradients (dual numbers), then kept where R = 0.
#pragma once

#include "interp/model.hpp"
#include "runtime/grid.hpp"

#include <array>
#include <vector>

namespace fortu {

struct SingularPoint {
    std::array<double, 3> point{};   ///< x, y[, z]
    int operations = 0;              ///< R-operations whose K_i vanishes here
};

/// A 2D R-operation whose operands vanish together along a whole curve (φ = −ψ there, as in a
/// disc conjoined with its own complement): K = 0 at every point of it, so it has no isolated
/// corners to report, and Newton's method, whose Jacobian is singular all along it, finds none.
struct SingularCurve {
    std::array<double, 3> point{};   ///< one point on it with R = 0, for the report
    int cells = 0;                   ///< search-grid cells it crosses
};

/// What the criterion finds: isolated points and (2D) curves.
struct SingularSet {
    std::vector<SingularPoint> points;
    std::vector<SingularCurve> curves;   ///< non-empty: the singular set is (partly) a curve
};

/// Singular points of the model on the search grid's box. 2D: isolated points, refined to
/// ~1e-12; points the solver cannot tell apart (closer than its position tolerance, which at
/// a tangency is the square root of its residual tolerance) are one point; an operation
/// whose operands share a curve of zeros gives a SingularCurve instead. 3D: singular points
/// lie on curves (edges); each seed cell gives one point on its curve, deduplicated to about
/// half a grid step. Points sorted by x, then y, then z.
SingularSet find_singular_set(const Model& model, const Grid& search_grid);
/// The points of find_singular_set.
std::vector<SingularPoint> find_singular_points(const Model& model, const Grid& search_grid);

/// The node K = ∏ (φ_i² + ψ_i²) over the model's R-operations (added to the model's graph);
/// the constant 1 when the model has none. For drawing K or evaluating it at a point.
ir::NodeId singular_criterion(Model& model);

}  // namespace fortu
