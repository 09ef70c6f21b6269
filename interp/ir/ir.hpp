// interp/ir/ir.hpp — the IR: a flat arena of SSA nodes with integer ids, forming a DAG in
// which equal sub-expressions are one node. Hash-consing and constant folding happen in the
// one function that makes nodes (Graph::make), so sharing is never a separate hope.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace fortu::ir {

enum class Op : uint8_t {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) name,
#include "interp/ir/ops.def"
#undef FORTU_OP
};

inline constexpr int kOpCount = 0
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) +1
#include "interp/ir/ops.def"
#undef FORTU_OP
    ;

enum OpFlags : unsigned {
    kLeaf = 1u << 0,         ///< no operands (Const, Arg)
    kCommutative = 1u << 1,  ///< operands are ordered by id before hashing
    kROperation = 1u << 2,   ///< an R-operation: imm is alpha
};

// Inline: the engines and the sign renderer ask per instruction in their hot loops.
inline int op_arity(Op op) {
    static constexpr int kArity[] = {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) arity,
#include "interp/ir/ops.def"
#undef FORTU_OP
    };
    return kArity[static_cast<int>(op)];
}

/// The operands whose sign alone decides the sign of an operation's result (bit k:
/// operand k), ops.def's sign_operands column.
enum SignOperands : unsigned {
    kSignOfNone = 0,
    kSignOfA = 1u << 0,                  ///< neg
    kSignOfAB = (1u << 0) | (1u << 1),   ///< min, max, R-operations
    kSignOfBC = (1u << 1) | (1u << 2),   ///< select(c, a, b): the signs of a and b, not of c
};

/// Whether the sign of op's result depends on operand k only through its sign (so that
/// operand may be replaced by anything with the same sign).
inline bool passes_sign(Op op, int k) {
    static constexpr unsigned kSignOperands[] = {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) (sign_operands),
#include "interp/ir/ops.def"
    };
    return (kSignOperands[static_cast<int>(op)] >> k) & 1u;
}

inline unsigned op_flags(Op op) {
    static constexpr unsigned kFlags[] = {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) (flags),
#include "interp/ir/ops.def"
#undef FORTU_OP
    };
    return kFlags[static_cast<int>(op)];
}
std::string_view op_name(Op op);

using NodeId = uint32_t;
inline constexpr NodeId kNoNode = ~NodeId{0};
inline constexpr int kMaxArity = 3;

struct Node {
    Op op = Op::Const;
    std::array<NodeId, kMaxArity> args{kNoNode, kNoNode, kNoNode};
    double imm = 0.0;   ///< Const: value; Arg: axis index; R-operations: alpha
};

/// The DAG. Operands always have smaller ids than their users, so id order is a
/// topological order.
class Graph {
public:
    /// Makes (or finds) the node op(args) with immediate imm; folds it when every operand
    /// is a constant and the result is a finite number (non-finite results are kept as
    /// nodes, so they show up as invalid points, not as silent constants).
    NodeId make(Op op, std::span<const NodeId> args = {}, double imm = 0.0);
    NodeId constant(double value) { return make(Op::Const, {}, value); }
    NodeId argument(int axis) { return make(Op::Arg, {}, static_cast<double>(axis)); }
    NodeId unary(Op op, NodeId a) { return make(op, std::array{a}); }
    NodeId binary(Op op, NodeId a, NodeId b, double imm = 0.0) {
        return make(op, std::array{a, b}, imm);
    }

    const Node& node(NodeId id) const { return nodes_[id]; }
    std::size_t size() const { return nodes_.size(); }
    bool is_constant(NodeId id) const { return nodes_[id].op == Op::Const; }
    double constant_value(NodeId id) const { return nodes_[id].imm; }
    /// Times make() returned an existing node instead of a new one (sharing by hash-consing).
    std::size_t reuse_count() const { return reuse_count_; }
    /// Ids of the nodes reachable from `root`, in topological (id) order.
    std::vector<NodeId> reachable(NodeId root) const { return reachable(std::span(&root, 1)); }
    /// The same for several roots, not looking past the nodes marked in `stop` (indexed by
    /// id; they are listed but their operands are not visited unless reached another way).
    std::vector<NodeId> reachable(std::span<const NodeId> roots, const std::vector<char>* stop = nullptr) const;

private:
    struct Key {
        Op op;
        std::array<NodeId, kMaxArity> args;
        uint64_t imm_bits;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const;
    };
    std::vector<Node> nodes_;
    std::unordered_map<Key, NodeId, KeyHash> index_;
    std::size_t reuse_count_ = 0;
};

/// The value of a node whose operands are the given constants (the constant folder's
/// evaluator; the same kernels the engines run).
double fold(Op op, double a, double b, double c, double imm);

}  // namespace fortu::ir
