// interp/quadrant_intervals.cpp — box_intervals.cpp's walk on four boxes at once: GCC vector
// types of four doubles (AVX2 where the build has it), per-lane interval_op where a lane
// leaves the written-out rules.
#include "interp/quadrant_intervals.hpp"

#include "interp/box_choice.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace fortu {
namespace {

using ir::Op;
using Lanes = double __attribute__((vector_size(32)));
using Mask = long long __attribute__((vector_size(32)));   ///< a comparison of Lanes: -1 or 0 per lane

#define FORTU_QUAD_INLINE inline __attribute__((always_inline))

FORTU_QUAD_INLINE Lanes load(const double* p) {
    Lanes v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
FORTU_QUAD_INLINE void store(double* p, Lanes v) { std::memcpy(p, &v, sizeof v); }
FORTU_QUAD_INLINE Lanes broadcast(double x) { return Lanes{x, x, x, x}; }
FORTU_QUAD_INLINE Mask finite(Lanes v) {
    const Lanes magnitude = (Lanes)((Mask)v & ~(Mask)broadcast(-0.0));
    return magnitude <= std::numeric_limits<double>::max();
}
FORTU_QUAD_INLINE bool all(Mask m) { return (m[0] & m[1] & m[2] & m[3]) != 0; }
/// The per-lane NaN bits of a slot as a mask.
FORTU_QUAD_INLINE Mask nan_mask(uint8_t bits) { return (Mask{1, 2, 4, 8} & (long long)bits) != 0; }
FORTU_QUAD_INLINE uint8_t nan_bits(Mask m) {
    return static_cast<uint8_t>((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8));
}
// std::min(a, b) is (b < a) ? b : a and std::max(a, b) is (a < b) ? b : a: the same per lane.
FORTU_QUAD_INLINE Lanes lane_min(Lanes a, Lanes b) { return b < a ? b : a; }
FORTU_QUAD_INLINE Lanes lane_max(Lanes a, Lanes b) { return a < b ? b : a; }

/// Four quadrants' operands or result: bounds per lane and NaN bits.
struct Quad {
    Lanes lo, hi;
    uint8_t nan;
};

FORTU_QUAD_INLINE Quad operand(const Instruction& ins, int k, const QuadrantScratch::Ranges* ranges,
                               const uint8_t* maybe_nan) {
    if ((ins.constant_operands >> k) & 1u) return {broadcast(ins.constant[k]), broadcast(ins.constant[k]), 0};
    const QuadrantScratch::Ranges& r = ranges[ins.in[k]];
    return {load(r.lo), load(r.hi), maybe_nan[ins.in[k]]};
}

/// The choice bytes' sign bits per lane: > 0 or < 0, where not maybe NaN.
FORTU_QUAD_INLINE Mask sign_bits(const Quad& r) {
    const Mask bits = ((r.lo > 0) & (long long)box_choice::kPositive) | ((r.hi < 0) & (long long)box_choice::kNegative);
    return bits & ~nan_mask(r.nan);
}

/// min(a, b) or max(a, b): box_choice::min_max_choice's predicates per lane.
template <bool kMin>
FORTU_QUAD_INLINE Mask min_max_predicates(const Quad& a, const Quad& b) {
    const Mask anan = nan_mask(a.nan), bnan = nan_mask(b.nan), numbers = ~(anan | bnan);
    const Mask apos = (a.lo > 0) & ~anan, aneg = (a.hi < 0) & ~anan;
    const Mask bpos = (b.lo > 0) & ~bnan, bneg = (b.hi < 0) & ~bnan;
    if constexpr (kMin)
        return (numbers & (a.hi < b.lo) & 1) | (numbers & (b.hi < a.lo) & 2) | (apos & 4) | (bpos & 8) |
               (aneg & ~bnan & 16) | (bneg & ~anan & 32);
    else
        return (numbers & (a.lo > b.hi) & 1) | (numbers & (b.lo > a.hi) & 2) | (aneg & 4) | (bneg & 8) |
               (apos & ~bnan & 16) | (bpos & ~anan & 32);
}

/// One lane by interval.cpp's rule (interval_op) and box_choice.hpp's choice.
__attribute__((noinline)) void general_lane(const Instruction& ins, int q, const QuadrantScratch::Ranges* ranges,
                                            const uint8_t* maybe_nan, Interval& out, uint8_t& choice) {
    Interval in[3];
    for (int k = 0; k < 3; ++k) {
        if ((ins.constant_operands >> k) & 1u) {
            in[k] = {ins.constant[k], ins.constant[k], false};
        } else {
            const QuadrantScratch::Ranges& r = ranges[ins.in[k]];
            in[k] = {r.lo[q], r.hi[q], ((maybe_nan[ins.in[k]] >> q) & 1u) != 0};
        }
    }
    out = interval_op(ins.op, in[0], in[1], in[2], ins.imm);
    choice = instruction_choice(ins, out, in[0], in[1], in[2]);
}

}  // namespace

void evaluate_quadrant_intervals(const Tape& tape, const std::array<std::array<Interval, 3>, 4>& axes,
                                 QuadrantScratch& s, std::array<std::vector<uint8_t>, 4>& choices,
                                 std::array<Interval, 4>& roots) {
    using box_choice::kUndecided;
    const std::size_t count = tape.code.size();
    s.ranges.resize(tape.slot_count);
    s.maybe_nan.resize(tape.slot_count);
    for (auto& c : choices) c.resize(count);
    QuadrantScratch::Ranges* const ranges = s.ranges.data();
    uint8_t* const maybe_nan = s.maybe_nan.data();
    ranges[tape.zero_slot] = {};
    maybe_nan[tape.zero_slot] = 0;
    for (auto [slot, axis] : tape.arguments) {
        uint8_t nan = 0;
        for (int q = 0; q < 4; ++q) {
            ranges[slot].lo[q] = axes[q][axis].lo;
            ranges[slot].hi[q] = axes[q][axis].hi;
            nan |= static_cast<uint8_t>(axes[q][axis].maybe_nan << q);
        }
        maybe_nan[slot] = nan;
    }
    for (auto [slot, value] : tape.constants) {
        store(ranges[slot].lo, broadcast(value));
        store(ranges[slot].hi, broadcast(value));
        maybe_nan[slot] = 0;
    }
    uint8_t* const choice[4] = {choices[0].data(), choices[1].data(), choices[2].data(), choices[3].data()};
    const Instruction* const code = tape.code.data();
    for (std::size_t i = 0; i < count; ++i) {
        const Instruction& ins = code[i];
        const Quad a = operand(ins, 0, ranges, maybe_nan);
        const Quad b = operand(ins, 1, ranges, maybe_nan);
        Quad r{a.lo, a.hi, static_cast<uint8_t>(a.nan | b.nan)};
        Mask bits = Mask{} | kUndecided;
        // The written-out rules of box_intervals.cpp on finite operands (b: the zero slot's
        // range for unary operations); `exact` false sends every lane to general_lane.
        bool exact = all(finite(a.lo) & finite(a.hi) & finite(b.lo) & finite(b.hi));
        bool checked = false;   // sum, difference, product, squared: non-finite or empty results are unknown
        if (exact) {
            switch (ins.op) {
            case Op::Add:
                r.lo = a.lo + b.lo, r.hi = a.hi + b.hi, checked = true;
                break;
            case Op::Sub:
                r.lo = a.lo - b.hi, r.hi = a.hi - b.lo, checked = true;
                break;
            case Op::Mul: {   // std::min({p, q, s, t}) and std::max({...}): first to last
                const Lanes p = a.lo * b.lo, q = a.lo * b.hi, u = a.hi * b.lo, t = a.hi * b.hi;
                r.lo = lane_min(lane_min(lane_min(p, q), u), t);
                r.hi = lane_max(lane_max(lane_max(p, q), u), t);
                checked = true;
                break;
            }
            case Op::Square: {
                const Lanes ll = a.lo * a.lo, hh = a.hi * a.hi;
                const Mask nonnegative = a.lo >= 0, nonpositive = a.hi <= 0;
                r.lo = nonnegative ? ll : nonpositive ? hh : broadcast(0.0);
                r.hi = nonnegative ? hh : nonpositive ? ll : lane_max(ll, hh);
                r.nan = a.nan;
                checked = true;
                break;
            }
            case Op::Min:
                r.lo = lane_min(a.lo, b.lo), r.hi = lane_min(a.hi, b.hi);
                bits = min_max_predicates<true>(a, b);
                break;
            case Op::Max:
                r.lo = lane_max(a.lo, b.lo), r.hi = lane_max(a.hi, b.hi);
                bits = min_max_predicates<false>(a, b);
                break;
            case Op::Neg:
                r.lo = -a.hi, r.hi = -a.lo, r.nan = a.nan;
                break;
            case Op::Abs: {
                const Mask nonnegative = a.lo >= 0, nonpositive = a.hi <= 0;
                r.lo = nonnegative ? a.lo : nonpositive ? -a.hi : broadcast(0.0);
                r.hi = nonnegative ? a.hi : nonpositive ? -a.lo : lane_max(-a.lo, a.hi);
                r.nan = a.nan;
                break;
            }
            case Op::Sqrt:
                if (!all(a.hi >= 0)) {
                    exact = false;
                    break;
                }
                for (int q = 0; q < 4; ++q) {
                    r.lo[q] = std::sqrt(std::max(a.lo[q], 0.0));
                    r.hi[q] = std::sqrt(a.hi[q]);
                }
                r.nan = a.nan | nan_bits(a.lo < 0);
                break;
            default:
                exact = false;
            }
        }
        if (checked) exact = all(finite(r.lo) & finite(r.hi) & (r.lo <= r.hi));
        QuadrantScratch::Ranges& out = ranges[ins.out];
        if (!exact) {
            for (int q = 0; q < 4; ++q) {
                Interval lane;
                general_lane(ins, q, ranges, maybe_nan, lane, choice[q][i]);
                out.lo[q] = lane.lo;
                out.hi[q] = lane.hi;
                maybe_nan[ins.out] = static_cast<uint8_t>((maybe_nan[ins.out] & ~(1u << q)) | (lane.maybe_nan << q));
            }
            continue;
        }
        store(out.lo, r.lo);
        store(out.hi, r.hi);
        maybe_nan[ins.out] = r.nan;
        const Mask sign = sign_bits(r);
        if (ins.op == Op::Min || ins.op == Op::Max) {
            for (int q = 0; q < 4; ++q) choice[q][i] = box_choice::min_max_choice(bits[q]) | static_cast<uint8_t>(sign[q]);
        } else {
            for (int q = 0; q < 4; ++q) choice[q][i] = static_cast<uint8_t>(bits[q] | sign[q]);
        }
    }
    for (int q = 0; q < 4; ++q)
        roots[q] = {ranges[tape.root_slot].lo[q], ranges[tape.root_slot].hi[q], ((maybe_nan[tape.root_slot] >> q) & 1u) != 0};
}

}  // namespace fortu
