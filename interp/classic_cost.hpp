// interp/classic_cost.hpp — the classic engine's cost per point, computed before running.
//
// Why: the classic engine re-evaluates shared sub-expressions, so its cost is the size of
// the fully expanded tree, which grows exponentially with nested R-operations (Bone.fortu:
// ~4·10⁸ operations per point). One pass over the DAG in topological order gives it
// exactly, so `fortu ir` can print it and `fortu run --engine classic` can refuse a run
// that would take hours, before spending them.
#pragma once

#include "interp/ir/ir.hpp"

namespace fortu {

/// Arithmetic operations the classic engine executes per point for the expression rooted
/// at `root`: the number of nodes of the fully expanded tree, an R-operation counting the
/// operations of its formula. A double: it can exceed
/// 2⁶⁴ for deep models.
double classic_operations_per_point(const ir::Graph& graph, ir::NodeId root);

/// How many times the classic engine evaluates operand k of node n per evaluation of n.
int classic_operand_uses(const ir::Node& n, int k);

/// Arithmetic operations node n executes itself per evaluation (operands excluded).
int classic_node_operations(const ir::Node& n);

}  // namespace fortu
