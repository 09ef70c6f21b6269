// interp/written_r_operations.cpp — the pattern, and one pass in id (topological) order that
// rebuilds what it changes.
#include "interp/written_r_operations.hpp"

#include <algorithm>
#include <vector>

namespace fortu {

bool written_r0(const ir::Graph& graph, ir::Op op, ir::NodeId x, ir::NodeId y, ir::NodeId& a, ir::NodeId& b) {
    if (op != ir::Op::Sub && op != ir::Op::Add) return false;
    const ir::NodeId operands[2] = {x, y};
    auto square_of = [&](ir::NodeId m) {
        const ir::Node& q = graph.node(m);
        if (q.op == ir::Op::Square) return q.args[0];
        if (q.op == ir::Op::Mul && q.args[0] == q.args[1]) return q.args[0];
        return ir::kNoNode;
    };
    // a + b − sqrt(…) is Sub(Add(a, b), Sqrt(…)); a + b + sqrt(…) is Add with its two
    // operands in either order (the graph orders a commutative operation's operands by id).
    for (int order = 0; order < (op == ir::Op::Add ? 2 : 1); ++order) {
        const ir::Node& sum = graph.node(operands[order]);
        const ir::Node& root = graph.node(operands[1 - order]);
        if (sum.op != ir::Op::Add || root.op != ir::Op::Sqrt) continue;
        const ir::Node& squares = graph.node(root.args[0]);
        if (squares.op != ir::Op::Add) continue;
        const ir::NodeId p = square_of(squares.args[0]), q = square_of(squares.args[1]);
        if ((p == sum.args[0] && q == sum.args[1]) || (p == sum.args[1] && q == sum.args[0])) {
            a = sum.args[0], b = sum.args[1];
            return true;
        }
    }
    return false;
}

namespace {

/// with_written_r0_as_operations over `nodes`, graph.reachable(root).
ir::NodeId rewrite(ir::Graph& graph, const std::vector<ir::NodeId>& nodes, ir::NodeId root) {
    std::vector<ir::NodeId> now(graph.size(), ir::kNoNode);   // by old id: its node in the result
    for (ir::NodeId id : nodes) {
        const ir::Node n = graph.node(id);   // a copy: make() may grow the node table
        ir::NodeId a, b;
        if (written_r0(graph, id, a, b)) {
            now[id] = r0_operation(graph, n.op, now[a], now[b]);
            continue;
        }
        const int arity = ir::op_arity(n.op);
        ir::NodeId args[ir::kMaxArity];
        bool changed = false;
        for (int k = 0; k < arity; ++k) {
            args[k] = now[n.args[k]];
            changed |= args[k] != n.args[k];
        }
        now[id] = changed ? graph.make(n.op, std::span(args, arity), n.imm) : id;
    }
    return now[root];
}

}  // namespace

ir::NodeId with_written_r0_as_operations(ir::Graph& graph, ir::NodeId root) {
    return rewrite(graph, graph.reachable(root), root);
}

Tape pruning_tape(const ir::Graph& graph, ir::NodeId root) {
    const std::vector<ir::NodeId> nodes = graph.reachable(root);
    const bool any = std::any_of(nodes.begin(), nodes.end(), [&](ir::NodeId id) {
        ir::NodeId a, b;
        return written_r0(graph, id, a, b);
    });
    auto ssa = [](ir::NodeId r) { return TapeSpec{{r}, {}, {}, /*reuse_slots=*/false}; };
    if (!any) return compile_tape(graph, ssa(root));
    ir::Graph rewritten = graph;
    return compile_tape(rewritten, ssa(rewrite(rewritten, nodes, root)));
}

}  // namespace fortu
