// interp/box_simplify.hpp — a tape shortened for one box of the domain: the tape-to-tape
// pass behind the sign renderer's pruning (libfive's per-region tape simplification).
//
// Why: over a small box most of a model does not matter. Given the range of every slot
// over the box (interval arithmetic, interval.hpp), a min/max whose one operand wins over
// the whole box is that operand; and since only the sign of the result is wanted, a node
// whose value matters only through its sign (its users pass signs: ops.def's sign_operands
// column — neg, min, max, select's branches, R-operations) collapses by
// sign(a &α b) = sign(min(a, b)), sign(a |α b) = sign(max(a, b)) and becomes ±1 where its
// own sign is decided (performance-notes.md ideas 4-7). What is left is compacted into a
// new tape of the same type, so the box's sub-boxes and points run only that, with the
// same lane kernel (prospero.vm's 6,361 operations become a few dozen at most leaves).
#pragma once

#include "interp/box_choice.hpp"
#include "interp/interval.hpp"
#include "interp/tape.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace fortu {

/// Working memory of simplify_for_sign, reused from box to box.
struct BoxScratch {
    struct Value {
        uint32_t slot = 0;
        bool constant = false;
        double number = 0.0;
    };
    std::vector<uint8_t> demand;      ///< per slot of the input: 0 dead, else kDemandSign | kDemandValue
    std::vector<Value> replacement;   ///< per slot of a live instruction: what replaces it (slot = ~0: itself)
    std::vector<Value> renamed;       ///< per slot of the input: its value in the output
    std::vector<uint32_t> live_code;  ///< indices of the live instructions, last first
};

/// `tape` (SSA, with slot ranges `ranges` over a box) shortened for the sign of its root
/// over that box: dead code dropped, won min/max and sign-decided R-operations replaced by
/// an operand, sign-decided values by ±1. `out` is an SSA tape whose root has the same sign
/// at every point of the box (the same value where only the exact rules applied), its slots
/// numbered densely. With `keep_values` the root's value is kept, not only its sign: only
/// the exact rules apply (a won min/max, a decided select), so the shortened tape computes
/// the same value bit for bit at every point of the box (the mesher's node values and
/// Newton steps, mesher.hpp).
void simplify_for_sign(const Tape& tape, const std::vector<Interval>& ranges, BoxScratch& scratch, Tape& out,
                       bool keep_values = false);

/// simplify_for_sign for the sign, from the choice bytes of the box (one per instruction
/// of `tape`, instruction_choice of its ranges) instead of its ranges: the same tape.
void simplify_for_sign(const Tape& tape, const std::vector<uint8_t>& choices, BoxScratch& scratch, Tape& out);

}  // namespace fortu
