// interp/singular.cpp — corner finding: grid seeds, Newton refinement, the R = 0 filter.
#include "interp/singular.hpp"

#include "interp/engine.hpp"
#include "interp/voxel_engine.hpp"

#include <algorithm>
#include <cmath>

namespace fortu {
namespace {

/// R-operation nodes reachable from the root (each once, however often it is shared).
std::vector<ir::NodeId> r_operations(const Model& model) {
    std::vector<ir::NodeId> ops;
    for (ir::NodeId id : model.graph.reachable(model.root))
        if (ir::op_flags(model.graph.node(id).op) & ir::kROperation) ops.push_back(id);
    return ops;
}

/// 1 + |∇f|, ignoring a non-finite gradient (at a corner sqrt(a² + b²) has none).
double scale_of(const PointValue& v) {
    const double g = std::hypot(v.gradient[0], v.gradient[1], v.gradient[2]);
    return 1.0 + (std::isfinite(g) ? g : 0.0);
}

/// True when the values at a cell's corners straddle zero (or touch it).
bool changes_sign(const double* v, int n) {
    double lo = v[0], hi = v[0];
    for (int i = 1; i < n; ++i) {
        if (!std::isfinite(v[i])) return false;
        lo = std::min(lo, v[i]);
        hi = std::max(hi, v[i]);
    }
    return std::isfinite(v[0]) && lo <= 0 && hi >= 0;
}

/// refine() stops once |φ| + |ψ| is within this fraction of the operands' scale.
constexpr double kResidualTolerance = 1e-13;
/// How far apart two converged points must be to be told apart. Where the two boundaries
/// cross, the residual grows linearly with the distance and points land ~1e-13 apart; where
/// they touch (Y & (Y - X^2) at the origin) it grows with the distance's square, so a
/// residual within kResidualTolerance only places the point within its square root (~3e-7)
/// and seeds from neighbouring cells stop at different points that close.
const double kPositionTolerance = 4 * std::sqrt(kResidualTolerance);

/// Newton's method on F = (φ, ψ) = 0 from p. 2D: the 2×2 system; 3D: the minimum-norm
/// Gauss–Newton step onto the curve φ = ψ = 0. Returns false when it does not converge.
bool refine(const PointEvaluator& phi, const PointEvaluator& psi, int dims, std::array<double, 3>& p,
            double scale) {
    for (int iteration = 0; iteration < 60; ++iteration) {
        const PointValue a = phi(p), b = psi(p);
        if (!std::isfinite(a.value) || !std::isfinite(b.value)) return false;
        const double residual = std::fabs(a.value) + std::fabs(b.value);
        if (residual <= kResidualTolerance * (scale_of(a) + scale_of(b)) * std::max(1.0, scale)) return true;
        // J J^T (2x2) for 3D; J itself for 2D. Solve for the step.
        const auto& ga = a.gradient;
        const auto& gb = b.gradient;
        std::array<double, 3> step{};
        if (dims == 2) {
            const double det = ga[0] * gb[1] - ga[1] * gb[0];
            if (std::fabs(det) < 1e-300) return false;
            step[0] = (a.value * gb[1] - b.value * ga[1]) / det;
            step[1] = (ga[0] * b.value - gb[0] * a.value) / det;
        } else {
            const double m00 = ga[0] * ga[0] + ga[1] * ga[1] + ga[2] * ga[2];
            const double m01 = ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2];
            const double m11 = gb[0] * gb[0] + gb[1] * gb[1] + gb[2] * gb[2];
            const double det = m00 * m11 - m01 * m01;
            if (std::fabs(det) < 1e-300) return false;
            const double l0 = (a.value * m11 - b.value * m01) / det;
            const double l1 = (m00 * b.value - m01 * a.value) / det;
            for (int k = 0; k < 3; ++k) step[k] = l0 * ga[k] + l1 * gb[k];
        }
        for (int k = 0; k < dims; ++k) p[k] -= step[k];
        if (std::hypot(step[0], step[1], step[2]) > 10 * scale) return false;  // ran away
    }
    return false;
}

/// 2D: whether φ and ψ vanish together along a curve through the seed cell at p: p taken
/// onto φ = 0 by Newton's method on φ alone, ψ vanishes there too and the two gradients are
/// parallel (where two boundaries cross or touch at an isolated point, the projection of a
/// cell's centre misses the point, so ψ does not vanish there, or the gradients are not
/// parallel). On success p is the point on the curve.
bool on_common_curve(const PointEvaluator& phi, const PointEvaluator& psi, std::array<double, 3>& p, double scale) {
    for (int iteration = 0; iteration < 30; ++iteration) {
        const PointValue a = phi(p);
        const double g2 = a.gradient[0] * a.gradient[0] + a.gradient[1] * a.gradient[1];
        if (!std::isfinite(a.value) || !(g2 > 0)) return false;
        if (std::fabs(a.value) <= kResidualTolerance * scale_of(a) * std::max(1.0, scale)) break;
        p[0] -= a.value * a.gradient[0] / g2;
        p[1] -= a.value * a.gradient[1] / g2;
    }
    const PointValue a = phi(p), b = psi(p);
    if (!std::isfinite(b.value)) return false;
    const double tolerance = 1e3 * kResidualTolerance * (scale_of(a) + scale_of(b)) * std::max(1.0, scale);
    if (!(std::fabs(a.value) + std::fabs(b.value) <= tolerance)) return false;
    const double cross = a.gradient[0] * b.gradient[1] - a.gradient[1] * b.gradient[0];
    const double norms = std::hypot(a.gradient[0], a.gradient[1]) * std::hypot(b.gradient[0], b.gradient[1]);
    return norms > 0 && std::fabs(cross) <= 1e-9 * norms;
}

/// Seed cells a curve must cross to be reported as one: a single cell could be a tangency
/// met exactly.
constexpr int kMinCurveCells = 3;

bool inside_box(const Grid& g, const std::array<double, 3>& p, double margin) {
    const Axis* axes[3] = {&g.x, &g.y, &g.z};
    for (int k = 0; k < g.dims; ++k)
        if (p[k] < axes[k]->min - margin || p[k] > axes[k]->max + margin) return false;
    return true;
}

}  // namespace

ir::NodeId singular_criterion(Model& model) {
    ir::NodeId k = model.graph.constant(1.0);
    for (ir::NodeId op : r_operations(model)) {
        const ir::Node n = model.graph.node(op);
        const ir::NodeId sum = model.graph.binary(ir::Op::Add, model.graph.unary(ir::Op::Square, n.args[0]),
                                                  model.graph.unary(ir::Op::Square, n.args[1]));
        k = model.graph.binary(ir::Op::Mul, k, sum);
    }
    return k;
}

std::vector<SingularPoint> find_singular_points(const Model& model, const Grid& g) {
    return find_singular_set(model, g).points;
}

SingularSet find_singular_set(const Model& model, const Grid& g) {
    const int dims = g.dims;
    const double h = std::max({g.x.step(), g.y.step(), dims == 3 ? g.z.step() : 0.0});
    const double extent = std::max({g.x.max - g.x.min, g.y.max - g.y.min, dims == 3 ? g.z.max - g.z.min : 0.0});
    const PointEvaluator model_at(model.graph, model.root);
    std::vector<SingularPoint> found;

    // Points the solver cannot tell apart are one; of them the one with the least residual
    // |φ| + |ψ| stands for it in 2D (at a tangency, the nearest to the true point).
    std::vector<double> residuals;
    auto add = [&](const std::array<double, 3>& p, double residual, double merge_distance) {
        for (std::size_t k = 0; k < found.size(); ++k) {
            const std::array<double, 3>& q = found[k].point;
            if (std::hypot(q[0] - p[0], q[1] - p[1], q[2] - p[2]) > merge_distance) continue;
            if (dims == 2 && residual < residuals[k]) found[k].point = p, residuals[k] = residual;
            return;
        }
        found.push_back(SingularPoint{p, 0});
        residuals.push_back(residual);
    };

    const std::vector<ir::NodeId> ops = r_operations(model);
    std::vector<std::pair<PointEvaluator, PointEvaluator>> operands;
    for (ir::NodeId op : ops) {
        const ir::Node& n = model.graph.node(op);
        operands.emplace_back(PointEvaluator(model.graph, n.args[0]), PointEvaluator(model.graph, n.args[1]));
    }
    const int corners = dims == 3 ? 8 : 4;
    const int slice_cells = dims == 3 ? g.slices() - 1 : 1;
    std::vector<SingularCurve> curves;
    for (std::size_t i = 0; i < ops.size(); ++i) {
        SingularCurve curve;
        const ir::Node& n = model.graph.node(ops[i]);
        const Field phi = evaluate_grid(model.graph, n.args[0], g, default_engine());
        const Field psi = evaluate_grid(model.graph, n.args[1], g, default_engine());
        const auto& [phi_at, psi_at] = operands[i];
        for (int s = 0; s < slice_cells; ++s)
            for (int r = 0; r + 1 < g.rows(); ++r)
                for (int c = 0; c + 1 < g.cols(); ++c) {
                    double a[8], b[8];
                    for (int k = 0; k < corners; ++k) {
                        const std::size_t at = g.index(c + (k & 1), r + ((k >> 1) & 1), s + (k >> 2));
                        a[k] = phi.values[at];
                        b[k] = psi.values[at];
                    }
                    if (!changes_sign(a, corners) || !changes_sign(b, corners)) continue;
                    std::array<double, 3> p{g.x_at(c) + g.x.step() / 2, g.y_at(r) - g.y.step() / 2,
                                            dims == 3 ? g.z_at(s) + g.z.step() / 2 : 0.0};
                    // R = 0: the point is on the model's boundary, not outside its region.
                    auto on_boundary = [&](const std::array<double, 3>& q) {
                        const PointValue r_value = model_at(q);
                        return std::fabs(r_value.value) <= 1e-9 * scale_of(r_value) * std::max(1.0, h);
                    };
                    const std::array<double, 3> seed = p;
                    if (!refine(phi_at, psi_at, dims, p, h)) {
                        std::array<double, 3> q = seed;
                        if (dims == 2 && on_common_curve(phi_at, psi_at, q, h) && inside_box(g, q, 1e-9 * extent) &&
                            on_boundary(q) && curve.cells++ == 0)
                            curve.point = q;
                        continue;
                    }
                    if (!inside_box(g, p, 1e-9 * extent)) continue;
                    if (!on_boundary(p)) continue;
                    add(p, std::fabs(phi_at(p).value) + std::fabs(psi_at(p).value),
                        dims == 3 ? h / 2 : kPositionTolerance * std::max(1.0, extent));
                }
        if (curve.cells >= kMinCurveCells) curves.push_back(curve);
    }
    for (SingularPoint& s : found) {
        for (const auto& [phi_at, psi_at] : operands)
            s.operations += std::fabs(phi_at(s.point).value) + std::fabs(psi_at(s.point).value) <= 1e-9 * std::max(1.0, h);
        for (double& v : s.point) {  // snap to 1e-12 so results read cleanly; no -0
            v = std::round(v * 1e12) / 1e12;
            if (v == 0) v = 0;
        }
    }
    std::sort(found.begin(), found.end(), [](const SingularPoint& a, const SingularPoint& b) {
        return a.point < b.point;
    });
    for (SingularCurve& c : curves)
        for (double& v : c.point) {
            v = std::round(v * 1e12) / 1e12;
            if (v == 0) v = 0;
        }
    return SingularSet{std::move(found), std::move(curves)};
}

}  // namespace fortu
