// interp/classic_cost.cpp — expanded-tree size by one topological pass.
#include "interp/classic_cost.hpp"

#include "interp/ir/kernels.hpp"

#include <vector>

namespace fortu {

int classic_node_operations(const ir::Node& n) {
    static constexpr int kOps[] = {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) formula_ops,
#include "interp/ir/ops.def"
#undef FORTU_OP
    };
    if (ir::op_flags(n.op) & ir::kROperation) return ir::r_formula_ops(n.imm);
    return kOps[static_cast<int>(n.op)];
}

int classic_operand_uses(const ir::Node& n, int k) {
    if (!(ir::op_flags(n.op) & ir::kROperation)) return 1;
    // Count the getter calls the one R-formula makes: the count can't drift from kernels.hpp.
    int uses[2] = {0, 0};
    auto get_a = [&] { ++uses[0]; return 1.0; };
    auto get_b = [&] { ++uses[1]; return 2.0; };
    if (n.op == ir::Op::RAnd) ir::r_conjunction(get_a, get_b, n.imm);
    else ir::r_disjunction(get_a, get_b, n.imm);
    return uses[k];
}

double classic_operations_per_point(const ir::Graph& graph, ir::NodeId root) {
    std::vector<double> cost(graph.size(), 0.0);
    for (ir::NodeId id : graph.reachable(root)) {
        const ir::Node& n = graph.node(id);
        double c = classic_node_operations(n);
        for (int k = 0; k < ir::op_arity(n.op); ++k) c += classic_operand_uses(n, k) * cost[n.args[k]];
        cost[id] = c;
    }
    return cost[root];
}

}  // namespace fortu
