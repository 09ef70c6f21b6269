// interp/box_simplify.cpp — the per-box shortening of an SSA tape: a backward pass that
// marks what each live value needs of its operands (box_choice.hpp says which operand a
// min/max wins with), then a forward pass that copies the kept instructions renumbered.
#include "interp/box_simplify.hpp"

namespace fortu {
namespace {

constexpr uint32_t kItself = ~uint32_t{0};
/// What a user demands of a slot (BoxScratch::demand): only its sign, or its value.
constexpr uint8_t kDemandSign = 1;
constexpr uint8_t kDemandValue = 2;

bool is_immediate(const Instruction& ins, int k) { return (ins.constant_operands >> k) & 1u; }

Interval operand_range(const Instruction& ins, int k, const std::vector<Interval>& ranges) {
    if (is_immediate(ins, k)) return {ins.constant[k], ins.constant[k], false};
    return ranges[ins.in[k]];
}

BoxScratch::Value constant_value(double number) { return {0, true, number}; }

/// The shortening, with `choice_of(i)` the choice byte of instruction i (box_choice.hpp).
template <class ChoiceOf>
void simplify(const Tape& tape, ChoiceOf choice_of, BoxScratch& s, Tape& out, bool keep_values) {
    using namespace box_choice;
    const uint32_t slots = tape.slot_count;
    s.demand.assign(slots, 0);
    if (s.replacement.size() < slots) s.replacement.resize(slots);
    if (s.renamed.size() < slots) s.renamed.resize(slots);
    s.live_code.clear();
    // Local pointers: through the vectors the compiler reloads each one's data pointer after
    // every store (they might alias), in the tightest loop of this pass.
    uint8_t* const demand = s.demand.data();
    BoxScratch::Value* const replacement = s.replacement.data();
    demand[tape.root_slot] = keep_values ? kDemandValue : kDemandSign;

    // Backward: what each live value needs of its operands (users come after operands). The
    // live instructions are listed, so the forward pass does not walk the dead ones again
    // (most of a long tape over a small box; the dead-or-live branch there was mispredicted).
    const Instruction* const code = tape.code.data();
    for (std::size_t i = tape.code.size(); i-- > 0;) {
        const Instruction& ins = code[i];
        const uint8_t wanted = demand[ins.out];
        if (!wanted) continue;
        s.live_code.push_back(static_cast<uint32_t>(i));
        const bool so = wanted == kDemandSign;
        const uint8_t choice = choice_of(i);
        if (so && (choice & (kPositive | kNegative))) {
            replacement[ins.out] = constant_value(choice & kPositive ? 1.0 : -1.0);
            continue;
        }
        const int chosen = so ? sign_operand(choice) : value_operand(choice);
        if (chosen != kNone) {
            if (is_immediate(ins, chosen)) {
                replacement[ins.out] = constant_value(ins.constant[chosen]);
            } else {
                const uint32_t operand = ins.in[chosen];
                replacement[ins.out] = {operand, false, 0.0};
                demand[operand] |= so ? kDemandSign : kDemandValue;
            }
            continue;
        }
        replacement[ins.out].slot = kItself;
        replacement[ins.out].constant = false;
        const int arity = ir::op_arity(ins.op);
        for (int k = 0; k < arity; ++k) {
            if (is_immediate(ins, k)) continue;
            demand[ins.in[k]] |= (so && ir::passes_sign(ins.op, k)) ? kDemandSign : kDemandValue;
        }
    }

    // Forward: the kept instructions, renumbered densely (SSA).
    out.code.clear();
    out.constants.clear();
    out.arguments.clear();
    out.inputs.clear();
    out.uniform_uses.clear();
    out.outputs.clear();
    out.zero_slot = 0;
    uint32_t next_slot = 1;
    for (auto [slot, axis] : tape.arguments) {
        if (!demand[slot]) continue;
        s.renamed[slot] = {next_slot, false, 0.0};
        out.arguments.emplace_back(next_slot++, axis);
    }
    for (auto [slot, value] : tape.constants) s.renamed[slot] = constant_value(value);
    out.code.reserve(s.live_code.size());
    for (std::size_t k = s.live_code.size(); k-- > 0;) {
        const Instruction& ins = code[s.live_code[k]];
        const BoxScratch::Value& rep = replacement[ins.out];
        if (rep.constant) {
            s.renamed[ins.out] = rep;
            continue;
        }
        if (rep.slot != kItself) {
            s.renamed[ins.out] = s.renamed[rep.slot];
            continue;
        }
        // Built in place: a copy assembled on the stack and pushed cost a store-forwarding
        // stall per instruction (a fifth of this pass on prospero.vm).
        Instruction& kept = out.code.emplace_back(ins);
        for (int k = 0; k < ir::op_arity(ins.op); ++k) {
            if (is_immediate(ins, k)) continue;
            const BoxScratch::Value& v = s.renamed[ins.in[k]];
            if (v.constant) {
                kept.constant_operands |= static_cast<uint8_t>(1u << k);
                kept.constant[k] = v.number;
                kept.in[k] = out.zero_slot;
            } else {
                kept.in[k] = v.slot;
            }
        }
        kept.out = next_slot++;
        s.renamed[ins.out] = {kept.out, false, 0.0};
    }
    const BoxScratch::Value root = s.renamed[tape.root_slot];
    if (root.constant) {
        out.root_slot = next_slot++;
        out.constants.emplace_back(out.root_slot, root.number);
    } else {
        out.root_slot = root.slot;
    }
    out.outputs.push_back(out.root_slot);
    out.slot_count = next_slot;
    out.node_count = out.code.size() + out.arguments.size() + out.constants.size();
}

}  // namespace

void simplify_for_sign(const Tape& tape, const std::vector<Interval>& ranges, BoxScratch& s, Tape& out,
                       bool keep_values) {
    // The choices of the live instructions only, from their ranges.
    auto choice_of = [&](std::size_t i) {
        const Instruction& ins = tape.code[i];
        return instruction_choice(ins, ranges[ins.out], operand_range(ins, 0, ranges), operand_range(ins, 1, ranges),
                                  operand_range(ins, 2, ranges));
    };
    simplify(tape, choice_of, s, out, keep_values);
}

void simplify_for_sign(const Tape& tape, const std::vector<uint8_t>& choices, BoxScratch& s, Tape& out) {
    simplify(tape, [&choices](std::size_t i) { return choices[i]; }, s, out, false);
}

}  // namespace fortu
