// interp/number_operands.cpp — see number_operands.hpp.
#include "interp/number_operands.hpp"

#include "interp/interval.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fortu {
namespace {

using ir::Op;

/// What is known of one value over the grid.
struct Facts {
    Interval range = kUnknownInterval;   ///< float64 values (interval.hpp's contract)
    double magnitude = std::numeric_limits<double>::infinity();   ///< ≥ |value| in float32
    bool number32 = false;                ///< never NaN in float32 (with magnitude < FLT_MAX)
    bool nonnegative32 = false;           ///< ≥ 0 or −0 in float32 (when a number)
};

const Facts kOpaque{};

/// One float32 rounding (2^-24 relative) and then some: a bound on a correctly rounded result
/// from a bound on the exact one. Double arithmetic on bounds far below 2^1000 rounds by less.
double rounded_up(double bound) { return bound * (1.0 + 0x1p-22); }

Facts constant_facts(double value) {
    Facts f;
    f.range = std::isnan(value) ? kUnknownInterval : Interval{value, value, false};
    f.magnitude = rounded_up(std::fabs(value));
    f.number32 = std::isfinite(value);
    f.nonnegative32 = value >= 0;
    return f;
}

/// An axis whose nodes run from `first` to `last`: the engines place them at x_at(i) (and
/// y_at, z_at), monotone in i, so these two are the extremes.
Facts axis_facts(double first, double last) {
    const double lo = std::min(first, last), hi = std::max(first, last);
    if (!std::isfinite(lo) || !std::isfinite(hi)) return kOpaque;
    Facts f;
    f.range = {lo, hi, false};
    f.magnitude = rounded_up(std::max(std::fabs(lo), std::fabs(hi)));
    f.number32 = true;
    f.nonnegative32 = lo >= 0;
    return f;
}

/// The facts of op(a, b, c); `same_ab`: a and b are one value (X * X is a square).
Facts apply(Op op, double imm, const Facts& a, const Facts& b, const Facts& c, bool same_ab) {
    if (op == Op::Mul && same_ab) return apply(Op::Square, imm, a, a, c, false);
    Facts f;
    f.range = interval_op(op, a.range, b.range, c.range, imm);
    bool number = false;   // from numbers, this operation gives a number (float32)
    switch (op) {
    case Op::Neg:
        number = a.number32;
        f.magnitude = a.magnitude;
        break;
    case Op::Abs:
        number = a.number32;
        f.magnitude = a.magnitude;
        f.nonnegative32 = true;
        break;
    case Op::Square:
        number = a.number32;
        f.magnitude = rounded_up(a.magnitude * a.magnitude);
        f.nonnegative32 = true;
        break;
    case Op::Sqrt:
        number = a.number32 && a.nonnegative32;
        f.magnitude = rounded_up(std::sqrt(a.magnitude));
        f.nonnegative32 = true;
        break;
    case Op::Add:
    case Op::Sub:
        number = a.number32 && b.number32;
        f.magnitude = rounded_up(a.magnitude + b.magnitude);
        f.nonnegative32 = op == Op::Add && a.nonnegative32 && b.nonnegative32;
        break;
    case Op::Mul:
        number = a.number32 && b.number32;
        f.magnitude = rounded_up(a.magnitude * b.magnitude);
        f.nonnegative32 = a.nonnegative32 && b.nonnegative32;
        break;
    case Op::Min:
    case Op::Max:
        number = a.number32 && b.number32;
        f.magnitude = std::max(a.magnitude, b.magnitude);
        f.nonnegative32 = op == Op::Min ? a.nonnegative32 && b.nonnegative32 : a.nonnegative32 || b.nonnegative32;
        break;
    case Op::RAnd:
    case Op::ROr:
        // α = 1 is MIN/MAX; α = 0: (a + b) ∓ sqrt(a² + b²), a square root of a sum of squares.
        if (imm == 1.0 || imm == 0.0) {
            number = a.number32 && b.number32;
            // α = 0: |a + b| and the root are ≤ |a| + |b|; the squares must not overflow either.
            const double squares = rounded_up(a.magnitude * a.magnitude + b.magnitude * b.magnitude);
            f.magnitude = imm == 1.0 ? std::max(a.magnitude, b.magnitude)
                                     : std::max(rounded_up(4 * (a.magnitude + b.magnitude)), squares);
        }
        break;
    default:
        break;
    }
    // Below float32's largest value, with room: no operation above overflowed to ∞.
    f.number32 = number && f.magnitude < 0x1p120;
    if (!f.number32) f.nonnegative32 = false;
    return f;
}

bool is_number(const Facts& f, Precision precision) {
    return precision == Precision::Float64 ? !f.range.maybe_nan && !f.range.unknown() : f.number32;
}

}  // namespace

std::vector<uint8_t> number_operands(const ir::Graph& graph, const TapeSpec& spec, const Tape& tape, const Grid& grid,
                                     Precision precision, std::size_t opaque_inputs) {
    const std::array<Facts, 3> axes{axis_facts(grid.x_at(0), grid.x_at(grid.x.nodes - 1)),
                                    axis_facts(grid.y_at(0), grid.y_at(grid.y.nodes - 1)),
                                    axis_facts(grid.z_at(0), grid.z_at(grid.z.nodes - 1))};

    // The graph's nodes first (id order is topological): inputs and uniforms hold node values.
    std::vector<Facts> node(graph.size());
    for (ir::NodeId id = 0; id < graph.size(); ++id) {
        const ir::Node& n = graph.node(id);
        if (n.op == Op::Const) node[id] = constant_facts(n.imm);
        else if (n.op == Op::Arg) node[id] = n.imm >= 0 && n.imm < 3 ? axes[std::size_t(n.imm)] : kOpaque;
        else {
            const auto operand = [&](int k) -> const Facts& {
                return n.args[k] == ir::kNoNode ? kOpaque : node[n.args[k]];
            };
            node[id] = apply(n.op, n.imm, operand(0), operand(1), operand(2), n.args[0] == n.args[1]);
        }
    }

    // Then the tape in order: a reused slot holds, at each instruction, its latest value.
    std::vector<Facts> slot(tape.slot_count, constant_facts(0.0));
    for (auto [s, axis] : tape.arguments) slot[s] = axes[std::size_t(axis)];
    for (auto [s, value] : tape.constants) slot[s] = constant_facts(value);
    for (auto [s, which] : tape.inputs) slot[s] = which < opaque_inputs ? kOpaque : node[spec.inputs[which]];
    std::vector<std::array<int, ir::kMaxArity>> uniform_of(tape.code.size(), {-1, -1, -1});
    for (const UniformUse& use : tape.uniform_uses) uniform_of[use.instruction][use.operand] = int(use.uniform);

    std::vector<uint8_t> numbers(tape.code.size(), 0);
    for (std::size_t i = 0; i < tape.code.size(); ++i) {
        const Instruction& ins = tape.code[i];
        Facts operand[ir::kMaxArity];
        for (int k = 0; k < ir::kMaxArity; ++k) {
            if (!((ins.constant_operands >> k) & 1u)) operand[k] = slot[ins.in[k]];
            else if (uniform_of[i][k] >= 0) operand[k] = node[spec.uniforms[std::size_t(uniform_of[i][k])]];
            else operand[k] = constant_facts(ins.constant[k]);
            if (k < ir::op_arity(ins.op) && is_number(operand[k], precision)) numbers[i] |= uint8_t(1u << k);
        }
        const bool same_ab = (ins.constant_operands & 3u) == 0 && ins.in[0] == ins.in[1];
        slot[ins.out] = apply(ins.op, ins.imm, operand[0], operand[1], operand[2], same_ab);
    }
    return numbers;
}

}  // namespace fortu
