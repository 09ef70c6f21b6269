// interp/hoist.cpp — axis-dependence masks and the boundary between hoisted and per-point nodes.
#include "interp/hoist.hpp"

#include <algorithm>

namespace fortu {

HoistPlan plan_hoisting(const ir::Graph& graph, const std::vector<ir::NodeId>& outputs,
                        const std::vector<ir::NodeId>& inputs, bool columns, bool rows) {
    HoistPlan plan;
    constexpr unsigned kX = 1, kEverywhere = 7;
    std::vector<char> stop(graph.size(), 0), output(graph.size(), 0);
    for (ir::NodeId id : inputs) stop[id] = 1;
    for (ir::NodeId id : outputs) output[id] = 1;
    const std::vector<ir::NodeId> order = graph.reachable(outputs, &stop);

    // Bit a of axes[id]: the node's value depends on coordinate a.
    std::vector<unsigned char> axes(graph.size(), 0);
    for (ir::NodeId id : order) {
        const ir::Node& n = graph.node(id);
        if (stop[id]) axes[id] = kEverywhere;
        else if (n.op == ir::Op::Arg) axes[id] = static_cast<unsigned char>(1u << static_cast<int>(n.imm));
        else
            for (int k = 0; k < ir::op_arity(n.op); ++k) axes[id] |= axes[n.args[k]];
    }
    auto hoisted = [&](ir::NodeId id) {
        return !stop[id] && !output[id] && axes[id] != 0 &&
               ((columns && axes[id] == kX) || (rows && !(axes[id] & kX)));
    };

    std::vector<char> listed(graph.size(), 0);
    for (ir::NodeId id : order) {
        const ir::Node& n = graph.node(id);
        if (hoisted(id)) {
            plan.hoisted_operations += !(ir::op_flags(n.op) & ir::kLeaf);
            continue;
        }
        if (stop[id]) continue;
        for (int k = 0; k < ir::op_arity(n.op); ++k) {
            const ir::NodeId a = n.args[k];
            if (!hoisted(a) || listed[a]) continue;
            listed[a] = 1;
            (axes[a] == kX ? plan.column_nodes : plan.row_nodes).push_back(a);
        }
    }
    return plan;
}

}  // namespace fortu
