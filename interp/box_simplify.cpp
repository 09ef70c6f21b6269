// interp/box_simplify.cpp — interval evaluation of an SSA tape and its per-box shortening.
#include "interp/box_simplify.hpp"

namespace fortu {
namespace {

using ir::Op;

constexpr uint32_t kItself = ~uint32_t{0};
constexpr int kNoOperand = -1;

bool is_immediate(const Instruction& ins, int k) { return (ins.constant_operands >> k) & 1u; }

Interval operand_range(const Instruction& ins, int k, const std::vector<Interval>& ranges) {
    if (is_immediate(ins, k)) return {ins.constant[k], ins.constant[k], false};
    return ranges[ins.in[k]];
}

/// The operand (0, 1, 2) that the instruction equals over the whole box — for the value,
/// or for the sign when only the sign is demanded; kNoOperand when none does.
int choose_operand(const Instruction& ins, const std::vector<Interval>& ranges, bool sign_only) {
    if (ins.op == Op::Select) {
        const Interval c = operand_range(ins, 0, ranges);
        if (c.positive()) return 1;
        if (c.hi <= 0 && !c.maybe_nan) return 2;
        return kNoOperand;
    }
    const bool is_min = ins.op == Op::Min || (ins.op == Op::RAnd && ins.imm == 1.0);
    const bool is_max = ins.op == Op::Max || (ins.op == Op::ROr && ins.imm == 1.0);
    const bool conj = is_min || ins.op == Op::RAnd;
    const bool disj = is_max || ins.op == Op::ROr;
    if (!conj && !disj) return kNoOperand;
    const Interval a = operand_range(ins, 0, ranges);
    const Interval b = operand_range(ins, 1, ranges);
    const bool numbers = !a.maybe_nan && !b.maybe_nan;
    // Exact: one operand is the minimum (maximum) at every point.
    if (is_min && numbers) {
        if (a.hi < b.lo) return 0;
        if (b.hi < a.lo) return 1;
    }
    if (is_max && numbers) {
        if (a.lo > b.hi) return 0;
        if (b.lo > a.hi) return 1;
    }
    if (!sign_only) return kNoOperand;
    // An R-formula with α ≠ 1 gives ∞ − ∞ = NaN from an infinite operand: finite ranges only.
    if (!is_min && !is_max && !(a.bounded() && b.bounded())) return kNoOperand;
    // sign(a & b) = sign(min(a, b)); sign(a | b) = sign(max(a, b)).
    if (conj) {
        if (a.positive()) return 1;
        if (b.positive()) return 0;
        if (a.negative() && !b.maybe_nan) return 0;
        if (b.negative() && !a.maybe_nan) return 1;
    } else {
        if (a.negative()) return 1;
        if (b.negative()) return 0;
        if (a.positive() && !b.maybe_nan) return 0;
        if (b.positive() && !a.maybe_nan) return 1;
    }
    return kNoOperand;
}

BoxScratch::Value constant_value(double number) { return {0, true, number}; }

}  // namespace

void simplify_for_sign(const Tape& tape, const std::vector<Interval>& ranges, BoxScratch& s, Tape& out,
                       bool keep_values) {
    const uint32_t slots = tape.slot_count;
    s.live.assign(slots, 0);
    s.sign_only.assign(slots, 1);
    s.replacement.assign(slots, BoxScratch::Value{kItself, false, 0.0});
    s.renamed.resize(slots);
    s.live_code.clear();
    s.live[tape.root_slot] = 1;
    s.sign_only[tape.root_slot] = keep_values ? 0 : 1;
    // Local pointers: through the vectors the compiler reloads each one's data pointer after
    // every store (they might alias), in the tightest loop of this pass.
    uint8_t* const live = s.live.data();

    // Backward: what each live value needs of its operands (users come after operands). The
    // live instructions are listed, so the forward pass does not walk the dead ones again
    // (most of a long tape over a small box; the dead-or-live branch there was mispredicted).
    for (std::size_t i = tape.code.size(); i-- > 0;) {
        const Instruction& ins = tape.code[i];
        if (!live[ins.out]) continue;
        s.live_code.push_back(static_cast<uint32_t>(i));
        const bool so = s.sign_only[ins.out];
        const Interval& r = ranges[ins.out];
        // ±1 for a value of one sign; a value that may be ±inf is kept (an R-formula of it is NaN).
        if (so && (r.positive() || r.negative()) && r.bounded()) {
            s.replacement[ins.out] = constant_value(r.positive() ? 1.0 : -1.0);
            continue;
        }
        const int choice = choose_operand(ins, ranges, so);
        if (choice != kNoOperand) {
            if (is_immediate(ins, choice)) {
                s.replacement[ins.out] = constant_value(ins.constant[choice]);
            } else {
                const uint32_t operand = ins.in[choice];
                s.replacement[ins.out] = {operand, false, 0.0};
                live[operand] = 1;
                s.sign_only[operand] &= so;
            }
            continue;
        }
        const int arity = ir::op_arity(ins.op);
        for (int k = 0; k < arity; ++k) {
            if (is_immediate(ins, k)) continue;
            live[ins.in[k]] = 1;
            s.sign_only[ins.in[k]] &= (so && ir::passes_sign(ins.op, k)) ? 1 : 0;
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
        if (!live[slot]) continue;
        s.renamed[slot] = {next_slot, false, 0.0};
        out.arguments.emplace_back(next_slot++, axis);
    }
    for (auto [slot, value] : tape.constants) s.renamed[slot] = constant_value(value);
    for (std::size_t k = s.live_code.size(); k-- > 0;) {
        const Instruction& ins = tape.code[s.live_code[k]];
        const BoxScratch::Value& rep = s.replacement[ins.out];
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

}  // namespace fortu
