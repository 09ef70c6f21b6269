// interp/hoist.cpp — axis-dependence masks and the boundary between hoisted and per-point nodes.
#include "interp/hoist.hpp"

#include <algorithm>

namespace fortu {

HoistPlan plan_hoisting(const ir::Graph& graph, const std::vector<ir::NodeId>& outputs,
                        const std::vector<ir::NodeId>& inputs, HoistKinds kinds) {
    HoistPlan plan;
    constexpr unsigned kX = 1, kY = 2, kZ = 4, kEverywhere = 7;
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
    auto kind_of = [&](ir::NodeId id) -> std::vector<ir::NodeId>* {
        if (stop[id] || output[id] || axes[id] == 0) return nullptr;
        if (axes[id] == kX) return kinds.columns ? &plan.column_nodes : nullptr;
        if (!(axes[id] & kX)) return kinds.rows ? &plan.row_nodes : nullptr;
        if (axes[id] == (kX | kY)) return kinds.xy_planes ? &plan.xy_plane_nodes : nullptr;
        if (axes[id] == (kX | kZ)) return kinds.xz_planes ? &plan.xz_plane_nodes : nullptr;
        return nullptr;
    };

    std::vector<char> listed(graph.size(), 0);
    for (ir::NodeId id : order) {
        const ir::Node& n = graph.node(id);
        if (kind_of(id)) {
            plan.hoisted_operations += !(ir::op_flags(n.op) & ir::kLeaf);
            continue;
        }
        if (stop[id]) continue;
        for (int k = 0; k < ir::op_arity(n.op); ++k) {
            const ir::NodeId a = n.args[k];
            std::vector<ir::NodeId>* kind = kind_of(a);
            if (!kind || listed[a]) continue;
            listed[a] = 1;
            kind->push_back(a);
        }
    }
    return plan;
}

}  // namespace fortu
