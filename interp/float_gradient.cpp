// interp/float_gradient.cpp — forward-mode derivatives in float32 lanes (float_gradient.hpp):
// each instruction's value by the float32 lane kernel, then its partial derivatives with
// respect to its operands (the rules of ir::Dual, kernels.hpp) as lanes, then
// d out = Σ partial × d operand for the three axes.
#include "interp/float_gradient.hpp"

#include "interp/lane_kernel.hpp"
#include "interp/vector_math.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fortu {
namespace {

using ir::Op;

/// The operands an operation's derivative depends on (0 for those whose derivative is 0).
int differentiated_operands(Op op, bool& supported) {
    supported = true;
    switch (op) {
    case Op::Const: case Op::Sign: case Op::Floor: case Op::Ceil: return 0;
    case Op::Neg: case Op::Square: case Op::Sqrt: case Op::Abs: case Op::Exp: case Op::Ln:
    case Op::Log10: case Op::Log2: case Op::Sin: case Op::Cos: case Op::Tan: case Op::Asin:
    case Op::Acos: case Op::Atan: case Op::Sinh: case Op::Cosh: case Op::Tanh: return 1;
    case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Pow: case Op::Atan2:
    case Op::Min: case Op::Max: case Op::Mod: case Op::Hypot: case Op::RAnd: case Op::ROr: return 2;
    case Op::Select: return 3;
    default: supported = false; return 0;
    }
}

/// sin or cos of every lane (SLEEF's vectors where this CPU has them).
void sine_lanes(Op op, const float* a, float* out, int n) {
    if (vector_math::has_vector_kernel(op) && vector_math::run_float(op, a, nullptr, 0.0f, 0.0f, 0, out, n)) return;
    for (int l = 0; l < n; ++l) out[l] = op == Op::Sin ? std::sin(a[l]) : std::cos(a[l]);
}

/// Fills pa, pb, pc with ∂out/∂operand per lane: a, b are the first two operands' values (the
/// third is never needed), o the output's, db the second operand's derivatives (Pow: whether
/// its exponent varies).
void partials(const Instruction& ins, const float* a, const float* b, const float* o,
              const std::array<const float*, 3>& db, float* pa, float* pb, float* pc, int n) {
    switch (ins.op) {
    case Op::Neg: std::fill_n(pa, n, -1.0f); break;
    case Op::Add: std::fill_n(pa, n, 1.0f), std::fill_n(pb, n, 1.0f); break;
    case Op::Sub: std::fill_n(pa, n, 1.0f), std::fill_n(pb, n, -1.0f); break;
    case Op::Mul: std::copy_n(b, n, pa), std::copy_n(a, n, pb); break;
    case Op::Div:
        for (int l = 0; l < n; ++l) pa[l] = 1.0f / b[l], pb[l] = -a[l] / (b[l] * b[l]);
        break;
    case Op::Square: for (int l = 0; l < n; ++l) pa[l] = 2.0f * a[l]; break;
    case Op::Sqrt: for (int l = 0; l < n; ++l) pa[l] = 0.5f / o[l]; break;
    case Op::Abs: for (int l = 0; l < n; ++l) pa[l] = a[l] < 0 ? -1.0f : 1.0f; break;
    case Op::Exp: std::copy_n(o, n, pa); break;
    case Op::Ln: for (int l = 0; l < n; ++l) pa[l] = 1.0f / a[l]; break;
    case Op::Log10: for (int l = 0; l < n; ++l) pa[l] = 1.0f / (a[l] * std::numbers::ln10_v<float>); break;
    case Op::Log2: for (int l = 0; l < n; ++l) pa[l] = 1.0f / (a[l] * std::numbers::ln2_v<float>); break;
    case Op::Sin: sine_lanes(Op::Cos, a, pa, n); break;
    case Op::Cos:
        sine_lanes(Op::Sin, a, pa, n);
        for (int l = 0; l < n; ++l) pa[l] = -pa[l];
        break;
    case Op::Tan: for (int l = 0; l < n; ++l) pa[l] = 1.0f + o[l] * o[l]; break;
    case Op::Asin: for (int l = 0; l < n; ++l) pa[l] = 1.0f / std::sqrt(1.0f - a[l] * a[l]); break;
    case Op::Acos: for (int l = 0; l < n; ++l) pa[l] = -1.0f / std::sqrt(1.0f - a[l] * a[l]); break;
    case Op::Atan: for (int l = 0; l < n; ++l) pa[l] = 1.0f / (1.0f + a[l] * a[l]); break;
    case Op::Atan2:   // atan2(y = a, x = b)
        for (int l = 0; l < n; ++l) {
            const float q = a[l] * a[l] + b[l] * b[l];
            pa[l] = b[l] / q, pb[l] = -a[l] / q;
        }
        break;
    case Op::Sinh: for (int l = 0; l < n; ++l) pa[l] = std::cosh(a[l]); break;
    case Op::Cosh: for (int l = 0; l < n; ++l) pa[l] = std::sinh(a[l]); break;
    case Op::Tanh: for (int l = 0; l < n; ++l) pa[l] = 1.0f - o[l] * o[l]; break;
    case Op::Min:
        for (int l = 0; l < n; ++l) pa[l] = (a[l] < b[l] || a[l] != a[l]) ? 1.0f : 0.0f, pb[l] = 1.0f - pa[l];
        break;
    case Op::Max:
        for (int l = 0; l < n; ++l) pa[l] = (a[l] > b[l] || a[l] != a[l]) ? 1.0f : 0.0f, pb[l] = 1.0f - pa[l];
        break;
    case Op::Mod: for (int l = 0; l < n; ++l) pa[l] = 1.0f, pb[l] = -std::trunc(a[l] / b[l]); break;
    case Op::Hypot: for (int l = 0; l < n; ++l) pa[l] = a[l] / o[l], pb[l] = b[l] / o[l]; break;
    case Op::Pow:
        for (int l = 0; l < n; ++l) {
            pa[l] = b[l] * std::pow(a[l], b[l] - 1.0f);
            const bool varies = db[0][l] != 0 || db[1][l] != 0 || db[2][l] != 0;
            pb[l] = varies ? o[l] * std::log(a[l]) : 0.0f;
        }
        break;
    case Op::RAnd:
    case Op::ROr: {
        const float alpha = static_cast<float>(ins.imm);
        if (ins.imm == 1.0) {   // min / max
            const bool conj = ins.op == Op::RAnd;
            for (int l = 0; l < n; ++l) {
                const bool first = conj ? (a[l] < b[l] || a[l] != a[l]) : (a[l] > b[l] || a[l] != a[l]);
                pa[l] = first ? 1.0f : 0.0f, pb[l] = 1.0f - pa[l];
            }
            break;
        }
        // (a + b ∓ s) / (1 + α), s = √(a² + b² − 2α a b): ∂s/∂a = (a − α b) / s.
        const float sign = ins.op == Op::RAnd ? -1.0f : 1.0f, scale = 1.0f / (1.0f + alpha);
        for (int l = 0; l < n; ++l) {
            const float s = std::sqrt(a[l] * a[l] + b[l] * b[l] - 2.0f * alpha * (a[l] * b[l]));
            pa[l] = (1.0f + sign * (a[l] - alpha * b[l]) / s) * scale;
            pb[l] = (1.0f + sign * (b[l] - alpha * a[l]) / s) * scale;
        }
        break;
    }
    case Op::Select:   // c > 0 ? a : (c is NaN ? c : b), operands (c, a, b)
        for (int l = 0; l < n; ++l) {
            pa[l] = 0.0f;
            pb[l] = a[l] > 0 ? 1.0f : 0.0f;
            pc[l] = !(a[l] > 0) && a[l] == a[l] ? 1.0f : 0.0f;
        }
        break;
    default: break;   // no derivative (Const, Sign, Floor, Ceil)
    }
}

}  // namespace

bool float_gradient_supported(const Tape& tape) {
    for (const Instruction& ins : tape.code) {
        bool supported;
        differentiated_operands(ins.op, supported);
        if (!supported) return false;
    }
    return true;
}

void float_gradients(const Tape& tape, const std::array<const float*, 3>& points, int count, float* value,
                     const std::array<float*, 3>& gradient, FloatGradientScratch& s) {
    const int n = count;
    const std::size_t slots = tape.slot_count, lanes = std::size_t(n);
    // Every instruction writes its slots before they are read: only the arguments', the
    // constants' and the zero slot's lanes need filling.
    if (s.values.size() < slots * lanes) s.values.resize(slots * lanes);
    if (s.derivatives.size() < slots * 3 * lanes) s.derivatives.resize(slots * 3 * lanes);
    // helper: operand broadcasts (3), zeros (1), partials (3).
    s.helper.assign(7 * lanes, 0.0f);
    s.value_slots.resize(slots);
    for (std::size_t k = 0; k < slots; ++k) s.value_slots[k] = s.values.data() + k * lanes;
    const auto derivative = [&](uint32_t slot, int axis) { return s.derivatives.data() + (slot * 3 + axis) * lanes; };
    const auto clear_derivatives = [&](uint32_t slot) {
        for (int axis = 0; axis < 3; ++axis) std::fill_n(derivative(slot, axis), n, 0.0f);
    };
    std::fill_n(s.value_slots[tape.zero_slot], n, 0.0f);
    clear_derivatives(tape.zero_slot);
    for (auto [slot, axis] : tape.arguments) {
        std::copy_n(points[axis], n, s.value_slots[slot]);
        clear_derivatives(slot);
        std::fill_n(derivative(slot, axis), n, 1.0f);
    }
    for (auto [slot, constant] : tape.constants) {
        std::fill_n(s.value_slots[slot], n, static_cast<float>(constant));
        clear_derivatives(slot);
    }
    float* broadcast[3] = {s.helper.data(), s.helper.data() + lanes, s.helper.data() + 2 * lanes};
    const float* zeros = s.helper.data() + 3 * lanes;
    float* partial[3] = {s.helper.data() + 4 * lanes, s.helper.data() + 5 * lanes, s.helper.data() + 6 * lanes};
    for (const Instruction& ins : tape.code) {
        run_lanes<float, 0>(&ins, 1, s.value_slots.data(), n);
        bool supported;
        const int arity = differentiated_operands(ins.op, supported);
        float* out[3] = {derivative(ins.out, 0), derivative(ins.out, 1), derivative(ins.out, 2)};
        if (arity == 0) {
            for (float* d : out) std::fill_n(d, n, 0.0f);
            continue;
        }
        const float* operand[3];
        std::array<std::array<const float*, 3>, 3> d_operand;
        for (int i = 0; i < 3; ++i) {
            const bool constant = (ins.constant_operands >> i) & 1;
            if (constant) std::fill_n(broadcast[i], n, static_cast<float>(ins.constant[i]));
            operand[i] = i >= arity ? zeros : constant ? broadcast[i] : s.value_slots[ins.in[i]];
            for (int axis = 0; axis < 3; ++axis)
                d_operand[i][axis] = i >= arity || constant ? zeros : derivative(ins.in[i], axis);
        }
        // Only the operands that vary contribute (a constant's derivative is 0, so is SELECT's
        // condition's); ADD, SUB and NEG add or subtract them without a partial.
        int varying[3], varying_count = 0;
        for (int i = ins.op == Op::Select ? 1 : 0; i < arity; ++i)
            if (!((ins.constant_operands >> i) & 1)) varying[varying_count++] = i;
        if (varying_count == 0) {
            for (float* d : out) std::fill_n(d, n, 0.0f);
            continue;
        }
        const bool linear = ins.op == Op::Add || ins.op == Op::Sub || ins.op == Op::Neg;
        if (!linear)
            partials(ins, operand[0], operand[1], s.value_slots[ins.out], d_operand[1], partial[0], partial[1],
                     partial[2], n);
        for (int axis = 0; axis < 3; ++axis) {
            float* __restrict d = out[axis];
            for (int v = 0; v < varying_count; ++v) {
                const int i = varying[v];
                const float* __restrict di = d_operand[i][axis];
                const float* __restrict pi = partial[i];
                const bool negated = ins.op == Op::Neg || (ins.op == Op::Sub && i == 1);
                if (linear && v == 0) {
                    if (negated) for (int l = 0; l < n; ++l) d[l] = -di[l];
                    else std::copy_n(di, n, d);
                } else if (linear) {
                    if (negated) for (int l = 0; l < n; ++l) d[l] -= di[l];
                    else for (int l = 0; l < n; ++l) d[l] += di[l];
                } else if (v == 0) {
                    for (int l = 0; l < n; ++l) d[l] = pi[l] * di[l];
                } else {
                    for (int l = 0; l < n; ++l) d[l] += pi[l] * di[l];
                }
            }
        }
    }
    std::copy_n(s.value_slots[tape.root_slot], n, value);
    for (int axis = 0; axis < 3; ++axis) std::copy_n(derivative(tape.root_slot, axis), n, gradient[axis]);
}

}  // namespace fortu
