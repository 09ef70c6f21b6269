// interp/written_r_operations.hpp — R0 written out as a formula, a + b ∓ sqrt(a² + b²), seen
// as the R-operation it is.
//
// Why: RANOK scripts often spell their R-operations so (the pawn's `E1 + E2 - SQRT(E1*E1 +
// E2*E2)`; 10 of the 56 in the RANOK folder). The value is the same, but interval arithmetic on the formula is loose (a and b
// each appear three times: [0, 1] ∧ [0, 1] gives [−1.4, 2], not [0, 1]), and its sign is not
// seen to be min(a, b)'s, so the interval-pruned walks (sign images and volumes, shaded
// views, meshes) decided little and shortened nothing there. As the R-operation node
// (RAnd / ROr with alpha 0) it gets the operation's own interval rule and the sign collapse,
// and computes the same IEEE operations in the same order (kernels.hpp, r_conjunction), so
// every value is the formula's, bit for bit.
#pragma once

#include "interp/ir/ir.hpp"
#include "interp/tape.hpp"

namespace fortu {

/// Whether op(x, y) is R0 written out as a formula: a + b − sqrt(a² + b²) (op Sub, a
/// conjunction) or a + b + sqrt(a² + b²) (op Add, either operand first: a disjunction), with
/// a² as a·a or SQUARE; `a` and `b` are set to its operands. For a node not made yet (the
/// `.vm` reader asks before making it).
bool written_r0(const ir::Graph& graph, ir::Op op, ir::NodeId x, ir::NodeId y, ir::NodeId& a, ir::NodeId& b);
/// The same for the node `id`.
inline bool written_r0(const ir::Graph& graph, ir::NodeId id, ir::NodeId& a, ir::NodeId& b) {
    const ir::Node& n = graph.node(id);
    return written_r0(graph, n.op, n.args[0], n.args[1], a, b);
}

/// The R-operation node (alpha 0) that op(x, y), a written R0 of operands `a` and `b` (as
/// written_r0 found), computes: RAnd for Sub, ROr for Add.
inline ir::NodeId r0_operation(ir::Graph& graph, ir::Op op, ir::NodeId a, ir::NodeId b) {
    return graph.binary(op == ir::Op::Sub ? ir::Op::RAnd : ir::Op::ROr, a, b, 0.0);
}

/// `root` with every written R0 it reaches made an RAnd / ROr node (alpha 0), the nodes added
/// to `graph`; `root` itself where there is none. Computes the same values bit for bit.
ir::NodeId with_written_r0_as_operations(ir::Graph& graph, ir::NodeId root);

/// The SSA tape (one slot per value) the interval-pruned walks run on (box_simplify.hpp):
/// `root`'s, with its written R0 as R-operations (on a copy of the graph where it has any).
Tape pruning_tape(const ir::Graph& graph, ir::NodeId root);

}  // namespace fortu
