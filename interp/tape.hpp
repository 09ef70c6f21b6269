// interp/tape.hpp — the DAG flattened into a linear SSA tape with register allocation: the
// one tape type every evaluator walks (the voxel engine's tiles, the hoisted column and row
// passes, the sign renderer's boxes), with one lane kernel (lane_kernel.hpp).
//
// Why: the voxel engine computes every node once per point, but keeping every node's
// values for every point would cost nodes × points memory. Walking the nodes in
// topological order and giving each value a slot that is reused after its last use keeps
// only the live values (prospero.vm: ~160 slots for 7866 nodes), and a slot holds one tile
// of points, so memory is slots × tile and fits in cache (performance-notes.md idea 1).
//
// A tape may have several outputs (the REPL keeps the values of its definitions), and
// nodes whose values come from outside instead of being computed: `inputs`, a lane array
// per tile (values kept from an earlier run, or computed once per grid column), and
// `uniforms`, one value per tile patched into the instructions as an immediate (computed
// once per grid row). Their operands are not on the tape unless reached another way.
#pragma once

#include "interp/ir/ir.hpp"

#include <cstdint>
#include <vector>

namespace fortu {

/// out := op(in...). An operand that is a constant is an immediate instead of a slot
/// (bit k of `constant_operands` set, value in `constant[k]`): constants then take no tile
/// memory (prospero.vm has 1406 of them) and the lane loops read a register.
struct Instruction {
    ir::Op op;
    uint8_t constant_operands = 0;
    uint32_t out;
    uint32_t in[ir::kMaxArity];
    double imm;
    double constant[ir::kMaxArity] = {0.0, 0.0, 0.0};
};

/// Whether `first` and `second` are the sin and cos (either order) of one operand read from
/// a slot: compile_tape puts such twins next to each other, and the float32 lanes (the lane
/// kernel and compiled tapes alike) compute them with one sincos (vector_math.hpp).
inline bool sincos_twins(const Instruction& first, const Instruction& second) {
    const bool ops = (first.op == ir::Op::Sin && second.op == ir::Op::Cos) ||
                     (first.op == ir::Op::Cos && second.op == ir::Op::Sin);
    return ops && first.constant_operands == 0 && second.constant_operands == 0 && first.in[0] == second.in[0] &&
           first.out != second.out;
}

struct TapeSpec {
    std::vector<ir::NodeId> outputs;    ///< computed and kept to the end; [0] is the model's root
    std::vector<ir::NodeId> inputs;     ///< supplied per tile as lane arrays
    std::vector<ir::NodeId> uniforms;   ///< supplied per tile as one value (never an output)
    /// false: SSA, one slot per value, never reused — for passes that look back at every
    /// value, as the sign renderer's per-box simplification does (box_simplify.hpp); the
    /// instructions then come in node id order. true: depth-first, each value close to its
    /// users (tape.cpp, locality_order), so fewer are alive at once.
    bool reuse_slots = true;
};

/// An instruction operand that reads a uniform: the engine writes the tile's value of
/// `uniforms[uniform]` into `code[instruction].constant[operand]`.
struct UniformUse {
    uint32_t instruction;
    uint32_t operand;
    uint32_t uniform;
};

struct Tape {
    std::vector<Instruction> code;     ///< non-leaf nodes in topological order
    uint32_t slot_count = 0;           ///< includes the argument and input slots
    std::vector<std::pair<uint32_t, double>> constants;  ///< slot, value (filled once): only a constant output
    std::vector<std::pair<uint32_t, int>> arguments;     ///< slot, axis (filled per tile)
    std::vector<std::pair<uint32_t, std::size_t>> inputs; ///< slot, index in TapeSpec::inputs (those reached)
    std::vector<UniformUse> uniform_uses;
    std::vector<uint32_t> outputs;     ///< slot of each TapeSpec::outputs entry
    uint32_t zero_slot = 0;            ///< all zeros: the unused operands read it
    uint32_t root_slot = 0;            ///< outputs[0]
    std::size_t node_count = 0;        ///< nodes reachable from the outputs (inputs and uniforms included)
};

Tape compile_tape(const ir::Graph& graph, const TapeSpec& spec);

/// Working memory of reallocate_slots, reused from call to call.
struct SlotScratch {
    std::vector<std::size_t> last_use;
    std::vector<uint32_t> renamed;
    std::vector<uint32_t> free_slots;
    std::vector<uint8_t> computed;
};

/// `ssa` (one slot per value, as the per-box simplification needs) with its slots reused
/// after their last use, as compile_tape allocates them: the same instructions in the same
/// order computing the same values, in max-live slots instead of one per node. Why: a box's
/// points are evaluated in lanes of slot_count × points, and a deep model that no box
/// simplifies would otherwise cost nodes × points (400,000 nodes × 125 points: 400 MB a
/// worker).
void reallocate_slots(const Tape& ssa, Tape& out, SlotScratch& scratch);
inline Tape compile_tape(const ir::Graph& graph, ir::NodeId root) { return compile_tape(graph, TapeSpec{{root}, {}, {}}); }

}  // namespace fortu
