// interp/compiled_tape_cache.hpp — compiled tapes found again by their content, for walks
// that shorten one model's tape region by region.
//
// Why: the shaded view shortens its tape for each region (box_simplify.hpp) and runs the
// result on a few hundred samples, too few to pay for compiling it; but regions side by side
// come out with the same tape (bear.vm's 1024² front view runs 30,652 leaves on 68 distinct
// tapes). Found again by content, a tape compiled once runs as machine code (tape_jit.hpp)
// in every leaf that has it, instead of the lane loops: the same values, bit for bit. A tape
// is compiled on its second sighting, since one seen once would cost its compilation and
// save nothing.
#pragma once

#include "interp/tape.hpp"
#include "interp/tape_jit.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace fortu {

/// One worker's compiled tapes (not shared: no locks on the walk's hot path).
template <class T>
class CompiledTapeCache {
public:
    /// At most `instruction_budget` instructions of compiled tapes are kept (their code and a
    /// copy of each tape to compare with); past it, new tapes run in the lane loops.
    explicit CompiledTapeCache(std::size_t instruction_budget = kDefaultInstructionBudget)
        : budget_(instruction_budget) {}

    /// The compiled code of a tape equal to `tape` (instructions, slots, arguments,
    /// constants), compiled now if this is its second sighting; nullptr where the lane loops
    /// should run it (first sighting, budget spent, no JIT on this CPU or build).
    const CompiledTape<T>* find(const Tape& tape);

    std::size_t compiled() const { return compiled_; }   ///< tapes compiled so far
    std::size_t hits() const { return hits_; }           ///< finds that returned code

    /// About 3.6 MiB of tape copies a worker (56 bytes an instruction), and their code.
    static constexpr std::size_t kDefaultInstructionBudget = 65536;

private:
    struct Entry {
        Tape tape;                              ///< what a later find compares with
        std::unique_ptr<CompiledTape<T>> code;  ///< null if compiling failed: the lane loops run it
    };
    std::unordered_map<uint64_t, uint32_t> sightings_;   ///< content hash → tapes seen, not compiled
    std::unordered_map<uint64_t, std::vector<Entry>> entries_;
    std::size_t budget_;
    std::size_t instructions_ = 0;
    std::size_t compiled_ = 0;
    std::size_t hits_ = 0;
};

/// A hash of everything compiled code depends on (same_tape_content's fields).
uint64_t tape_content_hash(const Tape& tape);
/// Whether compiled code for `a` computes `b` too: the same instructions (constant operands
/// bit for bit), slots, arguments, constants, inputs, uniforms and outputs.
bool same_tape_content(const Tape& a, const Tape& b);

extern template class CompiledTapeCache<float>;

}  // namespace fortu
