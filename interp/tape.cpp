// interp/tape.cpp — topological order, liveness, and linear-scan slot allocation.
#include "interp/tape.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <stdexcept>
#include <unordered_map>

namespace fortu {
namespace {

/// Sorts the few operands of a node (at most kMaxArity) by `before`, stably: an insertion sort,
/// which unlike std::stable_sort allocates nothing (this runs once per node).
template <class T, class Before>
void largest_first(T* items, int count, Before before) {
    for (int i = 1; i < count; ++i)
        for (int j = i; j > 0 && before(items[j], items[j - 1]); --j) std::swap(items[j], items[j - 1]);
}

/// Whether the tape computes `id`: neither a leaf (constant, argument) nor stopped at (an
/// input or uniform, supplied from outside).
bool computed_here(const ir::Graph& graph, const std::vector<char>& stop, ir::NodeId id) {
    return !stop[id] && !(ir::op_flags(graph.node(id).op) & ir::kLeaf);
}

/// The nodes `reachable` gives (the outputs and what they need, not past `stop`), in a
/// depth-first order: each node right after its operands, the operand that needs more
/// values alive at once first (Sethi–Ullman numbers, sharing ignored). Why: id order is
/// the order the model was written or imported in, and an imported .vm file may list its
/// nodes level by level (bear.vm: 40 divisions, then the next layer), so each value
/// waits hundreds of instructions for its user: compiled tapes load and store it around
/// that wait, and the lane loops keep its tile alive.
std::vector<ir::NodeId> locality_order(const ir::Graph& graph, std::span<const ir::NodeId> outputs,
                                       const std::vector<char>& stop) {
    const std::vector<ir::NodeId> reachable = graph.reachable(outputs, &stop);
    if (reachable.empty()) return reachable;
    const auto expands = [&](ir::NodeId id) { return computed_here(graph, stop, id); };
    // need[id]: registers to compute the node's tree (leaves are read from memory: 0).
    std::vector<uint32_t> need(graph.size(), 0);
    for (ir::NodeId id : reachable) {
        if (!expands(id)) continue;
        const ir::Node& n = graph.node(id);
        std::array<uint32_t, ir::kMaxArity> needs{};
        const int arity = ir::op_arity(n.op);
        for (int k = 0; k < arity; ++k) needs[k] = need[n.args[k]];
        largest_first(needs.data(), arity, [](uint32_t a, uint32_t b) { return a > b; });
        uint32_t most = 1;
        for (int k = 0; k < arity; ++k) most = std::max(most, needs[k] + uint32_t(k));
        need[id] = most;
    }
    std::vector<char> placed(graph.size(), 0);
    std::vector<ir::NodeId> order;
    order.reserve(reachable.size());
    struct Frame {
        ir::NodeId id;
        std::array<ir::NodeId, ir::kMaxArity> operands;
        int count;
        int next;
    };
    std::vector<Frame> stack;
    const auto enter = [&](ir::NodeId id) {
        Frame f{id, {}, 0, 0};
        if (expands(id)) {
            const ir::Node& n = graph.node(id);
            f.count = ir::op_arity(n.op);
            for (int k = 0; k < f.count; ++k) f.operands[k] = n.args[k];
            // The larger need first; ties keep the operands' own order.
            largest_first(f.operands.data(), f.count, [&](ir::NodeId a, ir::NodeId b) { return need[a] > need[b]; });
        }
        placed[id] = 1;   // entered: a DAG reaches it once
        stack.push_back(f);
    };
    for (ir::NodeId root : outputs) {
        if (placed[root]) continue;
        enter(root);
        while (!stack.empty()) {
            Frame& f = stack.back();
            if (f.next < f.count) {
                const ir::NodeId operand = f.operands[f.next++];
                if (!placed[operand]) enter(operand);
                continue;
            }
            order.push_back(f.id);
            stack.pop_back();
        }
    }
    return order;
}

/// `order` with the sin and cos of one operand side by side: the later of the two moves up
/// to just after the earlier (still after its operand, still before its users), so the float32
/// lanes compute both with one sincos (sincos_twins, vector_math.hpp).
std::vector<ir::NodeId> with_sincos_twins_adjacent(const ir::Graph& graph, std::vector<ir::NodeId> order,
                                                   const std::vector<char>& stop) {
    std::unordered_map<ir::NodeId, std::array<std::size_t, 2>> by_operand;   // operand: positions of sin, cos
    constexpr std::size_t kAbsent = ~std::size_t{0};
    for (std::size_t i = 0; i < order.size(); ++i) {
        const ir::NodeId id = order[i];
        const ir::Op op = graph.node(id).op;
        if ((op != ir::Op::Sin && op != ir::Op::Cos) || !computed_here(graph, stop, id)) continue;
        const ir::NodeId operand = graph.node(id).args[0];
        if (graph.node(operand).op == ir::Op::Const) continue;   // read as an immediate: no twin runs
        auto [it, added] = by_operand.try_emplace(operand, std::array<std::size_t, 2>{kAbsent, kAbsent});
        it->second[op == ir::Op::Sin ? 0 : 1] = i;
    }
    std::vector<std::size_t> twin_of(order.size(), kAbsent);
    bool any = false;
    for (const auto& [operand, at] : by_operand) {
        if (at[0] == kAbsent || at[1] == kAbsent) continue;
        twin_of[std::min(at[0], at[1])] = std::max(at[0], at[1]);
        twin_of[std::max(at[0], at[1])] = std::min(at[0], at[1]);
        any = true;
    }
    if (!any) return order;
    std::vector<ir::NodeId> paired;
    paired.reserve(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
        if (twin_of[i] != kAbsent && twin_of[i] < i) continue;   // placed beside its twin
        paired.push_back(order[i]);
        if (twin_of[i] != kAbsent) paired.push_back(order[twin_of[i]]);
    }
    return paired;
}

}  // namespace

Tape compile_tape(const ir::Graph& graph, const TapeSpec& spec) {
    Tape tape;
    constexpr uint32_t kNone = ~uint32_t{0};
    // What each node is, if not computed here: an input (its index) or a uniform.
    std::vector<uint32_t> input_index(graph.size(), kNone), uniform_index(graph.size(), kNone);
    std::vector<char> stop(graph.size(), 0);
    for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
        input_index[spec.inputs[i]] = static_cast<uint32_t>(i);
        stop[spec.inputs[i]] = 1;
    }
    for (std::size_t i = 0; i < spec.uniforms.size(); ++i) {
        uniform_index[spec.uniforms[i]] = static_cast<uint32_t>(i);
        stop[spec.uniforms[i]] = 1;
    }
    for (ir::NodeId out : spec.outputs)
        if (uniform_index[out] != kNone) throw std::logic_error("compile_tape: a uniform cannot be an output");
    // SSA tapes keep the ids' order: the per-box passes that walk them (box_simplify.hpp,
    // interval.hpp) cost the same in either, and the reordering would cost them its time.
    const std::vector<ir::NodeId> order = with_sincos_twins_adjacent(
        graph, spec.reuse_slots ? locality_order(graph, spec.outputs, stop) : graph.reachable(spec.outputs, &stop),
        stop);
    tape.node_count = order.size();
    // At most one instruction a node, reserved: grown by doubling, prospero.vm's 6,361 took
    // twice their 356 KB in fresh pages and copies (sign image 1024²: 0.6 → 0.45 ms to compile).
    tape.code.reserve(order.size());
    auto computed = [&](ir::NodeId id) { return computed_here(graph, stop, id); };

    // Last use of each node, as a position in `order` (outputs live to the end).
    std::vector<std::size_t> last_use(graph.size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i) {
        if (!computed(order[i])) continue;
        const ir::Node& n = graph.node(order[i]);
        for (int k = 0; k < ir::op_arity(n.op); ++k) last_use[n.args[k]] = i;
    }
    for (ir::NodeId out : spec.outputs) last_use[out] = order.size();

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

    // Arguments and inputs get permanent slots, filled per tile; constants are immediates
    // of the instructions that read them, and need a slot only as an output.
    for (ir::NodeId id : order) {
        const ir::Node& n = graph.node(id);
        if (input_index[id] != kNone) {
            slot[id] = next_slot++;
            tape.inputs.emplace_back(slot[id], input_index[id]);
        } else if (uniform_index[id] != kNone) {
            continue;
        } else if (n.op == ir::Op::Const && last_use[id] == order.size()) {
            slot[id] = next_slot++;
            tape.constants.emplace_back(slot[id], n.imm);
        } else if (n.op == ir::Op::Arg) {
            slot[id] = next_slot++;
            tape.arguments.emplace_back(slot[id], static_cast<int>(n.imm));
        }
    }

    for (std::size_t i = 0; i < order.size(); ++i) {
        const ir::NodeId id = order[i];
        if (!computed(id)) continue;
        const ir::Node& n = graph.node(id);
        Instruction ins{n.op, 0, 0, {tape.zero_slot, tape.zero_slot, tape.zero_slot}, n.imm, {0.0, 0.0, 0.0}};
        const int arity = ir::op_arity(n.op);
        for (int k = 0; k < arity; ++k) {
            const ir::NodeId a = n.args[k];
            ins.in[k] = slot[a];
            if (graph.node(a).op == ir::Op::Const || uniform_index[a] != kNone) {
                ins.constant_operands |= static_cast<uint8_t>(1u << k);
                ins.constant[k] = graph.node(a).imm;
                ins.in[k] = tape.zero_slot;
                if (uniform_index[a] != kNone)
                    tape.uniform_uses.push_back({static_cast<uint32_t>(tape.code.size()), static_cast<uint32_t>(k), uniform_index[a]});
            }
        }
        // The result gets its slot before the operands that die here are freed, so it never
        // shares a slot with an operand: the lane loops then take `restrict` pointers and
        // vectorise without run-time overlap checks.
        slot[id] = allocate();
        for (int k = 0; k < arity; ++k) {
            const ir::NodeId a = n.args[k];
            const bool seen_before = std::find(n.args.begin(), n.args.begin() + k, a) != n.args.begin() + k;
            if (spec.reuse_slots && computed(a) && !seen_before && last_use[a] == i) free_slots.push_back(slot[a]);
        }
        ins.out = slot[id];
        tape.code.push_back(ins);
    }
    for (ir::NodeId out : spec.outputs) tape.outputs.push_back(slot[out]);
    tape.root_slot = tape.outputs.empty() ? tape.zero_slot : tape.outputs[0];
    tape.slot_count = next_slot;
    return tape;
}

void reallocate_slots(const Tape& ssa, Tape& out, SlotScratch& s) {
    const std::size_t end = ssa.code.size();
    auto reads = [](const Instruction& ins, int k) { return !(ins.constant_operands & (1u << k)); };
    s.last_use.assign(ssa.slot_count, 0);
    s.computed.assign(ssa.slot_count, 0);
    for (std::size_t i = 0; i < end; ++i) {
        const Instruction& ins = ssa.code[i];
        s.computed[ins.out] = 1;
        for (int k = 0; k < ir::op_arity(ins.op); ++k)
            if (reads(ins, k)) s.last_use[ins.in[k]] = i;
    }
    for (uint32_t slot : ssa.outputs) s.last_use[slot] = end;

    s.renamed.assign(ssa.slot_count, 0);
    s.free_slots.clear();
    uint32_t next_slot = 0;
    out.zero_slot = next_slot++;
    s.renamed[ssa.zero_slot] = out.zero_slot;
    out.arguments.clear();
    out.constants.clear();
    out.inputs.clear();
    for (auto [slot, axis] : ssa.arguments) out.arguments.emplace_back(s.renamed[slot] = next_slot++, axis);
    for (auto [slot, value] : ssa.constants) out.constants.emplace_back(s.renamed[slot] = next_slot++, value);
    for (auto [slot, index] : ssa.inputs) out.inputs.emplace_back(s.renamed[slot] = next_slot++, index);
    auto allocate = [&]() -> uint32_t {
        if (s.free_slots.empty()) return next_slot++;
        const uint32_t slot = s.free_slots.back();
        s.free_slots.pop_back();
        return slot;
    };

    out.code.resize(end);
    for (std::size_t i = 0; i < end; ++i) {
        Instruction ins = ssa.code[i];
        const int arity = ir::op_arity(ins.op);
        for (int k = 0; k < arity; ++k)
            if (reads(ins, k)) ins.in[k] = s.renamed[ssa.code[i].in[k]];
        // As in compile_tape: the result never shares a slot with an operand (restrict).
        ins.out = s.renamed[ssa.code[i].out] = allocate();
        for (int k = 0; k < arity; ++k) {
            const uint32_t operand = ssa.code[i].in[k];
            bool seen_before = false;
            for (int j = 0; j < k; ++j) seen_before |= reads(ins, j) && ssa.code[i].in[j] == operand;
            if (reads(ins, k) && !seen_before && s.computed[operand] && s.last_use[operand] == i)
                s.free_slots.push_back(s.renamed[operand]);
        }
        if (s.last_use[ssa.code[i].out] <= i)
            s.free_slots.push_back(ins.out);   // never read: its slot serves the next result
        out.code[i] = ins;
    }
    out.uniform_uses = ssa.uniform_uses;
    out.outputs.clear();
    for (uint32_t slot : ssa.outputs) out.outputs.push_back(s.renamed[slot]);
    out.root_slot = out.outputs.empty() ? out.zero_slot : out.outputs[0];
    out.slot_count = next_slot;
    out.node_count = ssa.node_count;
}

}  // namespace fortu
