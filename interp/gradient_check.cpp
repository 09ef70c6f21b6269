// interp/gradient_check.cpp — one forward-mode pass over the DAG, node by node, stopping at
// the first derivative that is not finite. The engines compute the gradient in one sweep and
// cannot say where it broke; this pass exists so `fortu eval` and `:eval` can.
#include "interp/gradient_check.hpp"

#include "interp/ir/dual.hpp"
#include "interp/ir/kernels.hpp"

#include <cctype>
#include <cmath>
#include <fmt/format.h>
#include <vector>

namespace fortu {
namespace {

using namespace ir;  // kernel names are used unqualified inside ops.def expressions

Dual evaluate_node(const Node& n, const Dual& a, const Dual& b, const Dual& c, const Dual* coords) {
    using T = Dual;
    [[maybe_unused]] const double imm = n.imm;
    [[maybe_unused]] auto get_a = value_of(a);
    [[maybe_unused]] auto get_b = value_of(b);
    switch (n.op) {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) \
    case Op::name:                                                                         \
        if constexpr (Op::name == Op::Arg) {                                               \
            return coords[static_cast<int>(imm)];                                          \
        } else {                                                                           \
            return (expr);                                                                 \
        }
#include "interp/ir/ops.def"
#undef FORTU_OP
    }
    return T(kNaN);
}

bool finite(const Dual& x) {
    return std::isfinite(x.v) && std::isfinite(x.d[0]) && std::isfinite(x.d[1]) && std::isfinite(x.d[2]);
}

}  // namespace

std::optional<UndefinedGradient> find_undefined_gradient(const Graph& graph, NodeId root, std::array<double, 3> point) {
    Dual coords[3];
    for (int axis = 0; axis < 3; ++axis) coords[axis] = Dual::variable(point[axis], axis);
    std::vector<Dual> values(graph.size());
    for (NodeId id : graph.reachable(root)) {   // operands come first
        const Node& n = graph.node(id);
        const int arity = op_arity(n.op);
        const Dual zero(0.0);
        const Dual& a = arity > 0 ? values[n.args[0]] : zero;
        const Dual& b = arity > 1 ? values[n.args[1]] : zero;
        const Dual& c = arity > 2 ? values[n.args[2]] : zero;
        values[id] = evaluate_node(n, a, b, c, coords);
        if (finite(values[id])) continue;
        if (!std::isfinite(values[id].v)) return std::nullopt;   // an invalid value, not just its gradient
        return UndefinedGradient{id, n.op, {a.v, b.v, c.v}};
    }
    return std::nullopt;
}

std::string describe(const UndefinedGradient& cause) {
    std::string name;
    switch (cause.op) {
        case Op::RAnd: name = "R-conjunction"; break;
        case Op::ROr: name = "R-disjunction"; break;
        case Op::Pow: name = "^"; break;
        case Op::Square: name = "^2"; break;
        default:
            for (char ch : op_name(cause.op)) name += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    }
    std::string operands;
    const int arity = op_arity(cause.op);
    for (int i = 0; i < arity; ++i)
        operands += fmt::format("{}{}", i == 0 ? "" : i + 1 == arity ? " and " : ", ", cause.operands[i]);
    return fmt::format("{} of {}", name, operands);
}

}  // namespace fortu
