// interp/ir/ir.cpp — node construction: hash-consing and constant folding.
#include "interp/ir/ir.hpp"

#include "interp/ir/kernels.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace fortu::ir {

std::string_view op_name(Op op) {
    static constexpr std::string_view kNames[] = {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) spelling,
#include "interp/ir/ops.def"
#undef FORTU_OP
    };
    return kNames[static_cast<int>(op)];
}

double fold(Op op, double a, double b, double c, double imm) {
    using T = double;
    [[maybe_unused]] auto get_a = value_of(a);
    [[maybe_unused]] auto get_b = value_of(b);
    (void)c;
    switch (op) {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, sign_operands, interval, expr) \
    case Op::name: return (expr);
#include "interp/ir/ops.def"
#undef FORTU_OP
    }
    return kNaN;
}

std::size_t Graph::KeyHash::operator()(const Key& k) const {
    uint64_t h = static_cast<uint64_t>(k.op) * 0x9E3779B97F4A7C15ull;
    for (NodeId a : k.args) h = (h ^ a) * 0x100000001B3ull + (h >> 29);
    h ^= k.imm_bits + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
}

NodeId Graph::make(Op op, std::span<const NodeId> args, double imm) {
    Node node;
    node.op = op;
    node.imm = imm;
    const int arity = op_arity(op);
    for (int i = 0; i < arity; ++i) node.args[i] = args[i];
    if ((op_flags(op) & kCommutative) && arity == 2 && node.args[1] < node.args[0])
        std::swap(node.args[0], node.args[1]);

    if (arity > 0) {
        bool all_constant = true;
        double v[kMaxArity] = {0.0, 0.0, 0.0};
        for (int i = 0; i < arity; ++i) {
            all_constant = all_constant && is_constant(node.args[i]);
            if (all_constant) v[i] = constant_value(node.args[i]);
        }
        if (all_constant) {
            double folded = fold(op, v[0], v[1], v[2], imm);
            if (std::isfinite(folded)) return constant(folded);
        }
    }

    // Strength reduction: x^2 is by far the commonest power in R-function scripts, and
    // std::pow costs ~20x a multiplication. x*x is the correctly rounded square, as pow's.
    if (op == Op::Pow && is_constant(node.args[1]) && constant_value(node.args[1]) == 2.0)
        return make(Op::Square, std::array{node.args[0]});

    Key key{op, node.args, std::bit_cast<uint64_t>(imm)};
    auto [it, inserted] = index_.try_emplace(key, static_cast<NodeId>(nodes_.size()));
    if (!inserted) {
        ++reuse_count_;
        return it->second;
    }
    nodes_.push_back(node);
    return it->second;
}

std::vector<NodeId> Graph::reachable(std::span<const NodeId> roots, const std::vector<char>* stop) const {
    if (roots.empty()) return {};
    std::vector<char> seen(nodes_.size(), 0);
    NodeId last = 0;
    for (NodeId root : roots) {
        seen[root] = 1;
        last = std::max(last, root);
    }
    for (NodeId id = last + 1; id-- > 0;) {
        if (!seen[id] || (stop && (*stop)[id])) continue;
        const Node& n = nodes_[id];
        for (int i = 0; i < op_arity(n.op); ++i) seen[n.args[i]] = 1;
    }
    std::vector<NodeId> order;
    for (NodeId id = 0; id <= last; ++id)
        if (seen[id]) order.push_back(id);
    return order;
}

}  // namespace fortu::ir
