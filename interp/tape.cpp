// interp/tape.cpp — topological order, liveness, and linear-scan slot allocation.
#include "interp/tape.hpp"

#include <algorithm>

namespace fortu {

Tape compile_tape(const ir::Graph& graph, ir::NodeId root) {
    Tape tape;
    const std::vector<ir::NodeId> order = graph.reachable(root);
    tape.node_count = order.size();

    // Last use of each node, as a position in `order` (the root lives to the end).
    std::vector<std::size_t> position(graph.size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i) position[order[i]] = i;
    std::vector<std::size_t> last_use(graph.size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i) {
        const ir::Node& n = graph.node(order[i]);
        for (int k = 0; k < ir::op_arity(n.op); ++k) last_use[n.args[k]] = i;
    }
    last_use[root] = order.size();

    std::vector<uint32_t> slot(graph.size(), 0);
    std::vector<uint32_t> free_slots;
    uint32_t next_slot = 0;
    tape.zero_slot = next_slot++;
    auto allocate = [&]() -> uint32_t {
        if (free_slots.empty()) return next_slot++;
        const uint32_t s = free_slots.back();
        free_slots.pop_back();
        return s;
    };

    // Arguments get permanent slots, filled per tile; constants are immediates of the
    // instructions that read them, and need a slot only as the root (a constant model).
    for (ir::NodeId id : order) {
        const ir::Node& n = graph.node(id);
        if (n.op == ir::Op::Const && id == root) {
            slot[id] = next_slot++;
            tape.constants.emplace_back(slot[id], n.imm);
        } else if (n.op == ir::Op::Arg) {
            slot[id] = next_slot++;
            tape.arguments.emplace_back(slot[id], static_cast<int>(n.imm));
        }
    }

    for (std::size_t i = 0; i < order.size(); ++i) {
        const ir::NodeId id = order[i];
        const ir::Node& n = graph.node(id);
        if (ir::op_flags(n.op) & ir::kLeaf) continue;
        Instruction ins{n.op, 0, 0, {tape.zero_slot, tape.zero_slot, tape.zero_slot}, n.imm, {0.0, 0.0, 0.0}};
        const int arity = ir::op_arity(n.op);
        for (int k = 0; k < arity; ++k) {
            ins.in[k] = slot[n.args[k]];
            if (graph.node(n.args[k]).op == ir::Op::Const) {
                ins.constant_operands |= static_cast<uint8_t>(1u << k);
                ins.constant[k] = graph.node(n.args[k]).imm;
                ins.in[k] = tape.zero_slot;
            }
        }
        // The result gets its slot before the operands that die here are freed, so it never
        // shares a slot with an operand: the lane loops then take `restrict` pointers and
        // vectorise without run-time overlap checks.
        slot[id] = allocate();
        for (int k = 0; k < arity; ++k) {
            const ir::NodeId a = n.args[k];
            const bool leaf = ir::op_flags(graph.node(a).op) & ir::kLeaf;
            const bool seen_before = std::find(n.args.begin(), n.args.begin() + k, a) != n.args.begin() + k;
            if (!leaf && !seen_before && last_use[a] == i) free_slots.push_back(slot[a]);
        }
        ins.out = slot[id];
        tape.code.push_back(ins);
    }
    tape.root_slot = slot[root];
    tape.slot_count = next_slot;
    return tape;
}

}  // namespace fortu
