// interp/classic_engine.cpp — recursive, point-by-point, call-by-name evaluation.
#include "interp/classic_engine.hpp"

#include "interp/ir/kernels.hpp"
#include "interp/parallel.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace fortu {
namespace {

using namespace ir;  // kernel names are used unqualified inside ops.def expressions
using ir::Node;
using ir::NodeId;
using ir::Op;

template <class T>
class ClassicWalker {
public:
    ClassicWalker(const ir::Graph& graph, const T* coords) : graph_(graph), coords_(coords) {}

    T eval(NodeId id) const {
        const Node& n = graph_.node(id);
        [[maybe_unused]] const double imm = n.imm;
        // Counting every evaluation is also what keeps this engine honest: without a side
        // effect GCC proves eval() pure (once sqrt sets no errno) and merges the repeated
        // operand evaluations of an R-formula — memoising the engine that must not memoise.
        ++evaluations_;
        switch (n.op) {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr)                         \
    case Op::name:                                                                        \
        if constexpr (Op::name == Op::Arg) {                                              \
            return coords_[static_cast<int>(n.imm)];                                      \
        } else if constexpr (Op::name == Op::Const) {                                     \
            return T(n.imm);                                                              \
        } else {                                                                          \
            if constexpr (((flags) & ir::kROperation) != 0) {                             \
                /* the formula re-evaluates an operand at each of its references */       \
                auto get_a = [&] { return eval(n.args[0]); };                             \
                auto get_b = [&] { return eval(n.args[1]); };                             \
                [[maybe_unused]] const T a(0.0), b(0.0), c(0.0); /* unused by R-ops */     \
                return (expr);                                                            \
            } else {                                                                      \
                [[maybe_unused]] const T a = (arity) > 0 ? eval(n.args[0]) : T(0.0);      \
                [[maybe_unused]] const T b = (arity) > 1 ? eval(n.args[1]) : T(0.0);      \
                [[maybe_unused]] const T c = (arity) > 2 ? eval(n.args[2]) : T(0.0);      \
                [[maybe_unused]] auto get_a = ir::value_of(a);                            \
                [[maybe_unused]] auto get_b = ir::value_of(b);                            \
                return (expr);                                                            \
            }                                                                             \
        }
#include "interp/ir/ops.def"
#undef FORTU_OP
        }
        return T(ir::kNaN);
    }

    /// Node evaluations so far: the expanded tree's node count, once per point.
    std::uint64_t evaluations() const { return evaluations_; }

private:
    const ir::Graph& graph_;
    const T* coords_;
    mutable std::uint64_t evaluations_ = 0;
};

}  // namespace

Field ClassicEngine::evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid,
                                   const EvalOptions& options, const NodeValues& reuse) const {
    if (!reuse.empty())
        throw std::invalid_argument("known and kept node values are the voxel engine's (the classic engine saves nothing)");
    Field field = Field::filled(grid, std::nan(""), options.threads);
    const std::size_t rows_total = static_cast<std::size_t>(grid.rows()) * grid.slices();
    parallel_for(rows_total, options, [&](std::size_t line, int) {
        const int row = static_cast<int>(line % grid.rows());
        const int slice = static_cast<int>(line / grid.rows());
        double coords[3] = {0.0, grid.y_at(row), grid.z_at(slice)};
        ClassicWalker<double> walker(graph, coords);
        double* out = field.values.data() + grid.index(0, row, slice);
        for (int col = 0; col < grid.cols(); ++col) {
            coords[0] = grid.x_at(col);
            out[col] = walker.eval(root);
        }
        return static_cast<std::size_t>(grid.cols());
    });
    return field;
}

PointValue ClassicEngine::evaluate_point(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point) const {
    ir::Dual coords[3];
    for (int axis = 0; axis < 3; ++axis) coords[axis] = ir::Dual::variable(point[axis], axis);
    ClassicWalker<ir::Dual> walker(graph, coords);
    ir::Dual r = walker.eval(root);
    return PointValue{r.v, {r.d[0], r.d[1], r.d[2]}};
}

std::uint64_t classic_node_evaluations(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point) {
    ClassicWalker<double> walker(graph, point.data());
    walker.eval(root);
    return walker.evaluations();
}

}  // namespace fortu
