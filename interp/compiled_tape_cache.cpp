// interp/compiled_tape_cache.cpp — a hash to find candidates, an exact comparison to accept
// one: a wrong picture from a hash collision is not a risk worth a microsecond.
#include "interp/compiled_tape_cache.hpp"

#include <bit>

namespace fortu {
namespace {

/// One step of a multiply-xorshift hash over 64-bit words.
uint64_t mix(uint64_t h, uint64_t word) {
    h ^= word + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
    return h ^ (h >> 32);
}

/// Hashes of tapes seen once, kept until there are this many (then forgotten): a model whose
/// regions all differ would otherwise grow the table with every leaf.
constexpr std::size_t kMaxSightings = 1 << 16;

uint64_t bits(double value) { return std::bit_cast<uint64_t>(value); }

bool same_instruction(const Instruction& a, const Instruction& b) {
    if (a.op != b.op || a.constant_operands != b.constant_operands || a.out != b.out || bits(a.imm) != bits(b.imm))
        return false;
    for (int k = 0; k < ir::kMaxArity; ++k)
        if (a.in[k] != b.in[k] || bits(a.constant[k]) != bits(b.constant[k])) return false;
    return true;
}

}  // namespace

uint64_t tape_content_hash(const Tape& tape) {
    uint64_t h = mix(tape.code.size(), tape.slot_count);
    h = mix(h, uint64_t(tape.root_slot) << 32 | tape.zero_slot);
    for (const Instruction& ins : tape.code) {
        h = mix(h, uint64_t(ins.op) | uint64_t(ins.constant_operands) << 8 | uint64_t(ins.out) << 32);
        h = mix(h, uint64_t(ins.in[0]) | uint64_t(ins.in[1]) << 32);
        h = mix(h, uint64_t(ins.in[2]) ^ bits(ins.imm));
        // Constant operands only where they are read: the others are zero anyway.
        if (ins.constant_operands)
            for (int k = 0; k < ir::kMaxArity; ++k) h = mix(h, bits(ins.constant[k]));
    }
    for (auto [slot, axis] : tape.arguments) h = mix(h, uint64_t(slot) << 8 | uint64_t(axis));
    for (auto [slot, value] : tape.constants) h = mix(mix(h, slot), bits(value));
    return h;
}

bool same_tape_content(const Tape& a, const Tape& b) {
    if (a.code.size() != b.code.size() || a.slot_count != b.slot_count || a.root_slot != b.root_slot ||
        a.zero_slot != b.zero_slot || a.arguments != b.arguments || a.inputs != b.inputs || a.outputs != b.outputs ||
        a.uniform_uses.size() != b.uniform_uses.size() || a.constants.size() != b.constants.size())
        return false;
    for (std::size_t i = 0; i < a.constants.size(); ++i)
        if (a.constants[i].first != b.constants[i].first || bits(a.constants[i].second) != bits(b.constants[i].second))
            return false;
    for (std::size_t i = 0; i < a.uniform_uses.size(); ++i) {
        const UniformUse &u = a.uniform_uses[i], &v = b.uniform_uses[i];
        if (u.instruction != v.instruction || u.operand != v.operand || u.uniform != v.uniform) return false;
    }
    for (std::size_t i = 0; i < a.code.size(); ++i)
        if (!same_instruction(a.code[i], b.code[i])) return false;
    return true;
}

template <class T>
const CompiledTape<T>* CompiledTapeCache<T>::find(const Tape& tape) {
    const uint64_t hash = tape_content_hash(tape);
    if (auto found = entries_.find(hash); found != entries_.end())
        for (const Entry& entry : found->second)
            if (same_tape_content(entry.tape, tape)) {
                if (entry.code) ++hits_;
                return entry.code.get();
            }
    if (instructions_ + tape.code.size() > budget_ || !tape_jit_available()) return nullptr;
    // A second sighting of the hash: almost surely this tape, and if not, compiling it costs
    // only the time.
    if (sightings_.size() >= kMaxSightings) sightings_.clear();
    uint32_t& seen = sightings_[hash];
    if (++seen < 2) return nullptr;
    sightings_.erase(hash);
    Entry& entry = entries_[hash].emplace_back(Entry{tape, CompiledTape<T>::compile(tape)});
    instructions_ += tape.code.size();
    if (!entry.code) return nullptr;
    ++compiled_;
    ++hits_;
    return entry.code.get();
}

template class CompiledTapeCache<float>;

}  // namespace fortu
