// interp/tape.hpp — the DAG flattened into a linear SSA tape with register allocation.
//
// Why: the voxel engine computes every node once per point, but keeping every node's
// values for every point would cost nodes × points memory. Walking the nodes in
// topological order and giving each value a slot that is reused after its last use keeps
// only the live values (prospero.vm: ~160 slots for 7866 nodes), and a slot holds one tile
// of points, so memory is slots × tile and fits in cache (performance-notes.md idea 1).
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

struct Tape {
    std::vector<Instruction> code;     ///< non-leaf nodes in topological order
    uint32_t slot_count = 0;           ///< includes the constant and argument slots
    std::vector<std::pair<uint32_t, double>> constants;  ///< slot, value (filled once): only a constant root
    std::vector<std::pair<uint32_t, int>> arguments;     ///< slot, axis (filled per tile)
    uint32_t zero_slot = 0;            ///< all zeros: the unused operands read it
    uint32_t root_slot = 0;
    std::size_t node_count = 0;        ///< nodes reachable from the root
};

Tape compile_tape(const ir::Graph& graph, ir::NodeId root);

}  // namespace fortu
