// interp/float32_bound.cpp — the forward error analysis: one rule per operation, from its
// Lipschitz bound over the widened operand ranges and the rounding of its result. Where that
// fails (a range with an infinite bound: 0.1/x across x = 0 in bear.vm), a value keeps the
// range its float32 evaluation can take instead, found by the interval rules on its operands'
// float32 ranges, widened by float32's rounding; once a result's float64 and float32 ranges
// are both finite (exp(−30.6·max(…, |that|)) is in [0, e^c]) their hull's width bounds its
// error, and the analysis goes on from there.
#include "interp/float32_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fortu {
namespace {

using ir::Op;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFloat32Unit = 0x1p-24;       ///< correctly rounded float32: half an ulp
constexpr double kFloat64Unit = 0x1p-53;
constexpr double kFloat32Function = 0x1p-22;   ///< SLEEF u10 / u05 functions: within 1 ulp, taken as 2
constexpr double kFloat64Function = 0x1p-50;   ///< glibc's double functions: within a few ulps
constexpr double kSubnormal = 0x1p-126;        ///< float32's absolute error below its normal range
/// Beyond this magnitude float32 may overflow (3.4e38) in a product or a square.
constexpr double kFloat32Safe = 1e18;

double magnitude(const Interval& r) { return std::max(std::abs(r.lo), std::abs(r.hi)); }
/// The smallest |x| over the range.
double mignitude(const Interval& r) { return (r.lo <= 0 && r.hi >= 0) ? 0.0 : std::min(std::abs(r.lo), std::abs(r.hi)); }

/// Rounding of a result of magnitude at most m in both formats.
double rounded(double m) { return (kFloat32Unit + kFloat64Unit) * m + kSubnormal; }
double rounded_function(double m) { return (kFloat32Function + kFloat64Function) * m + kSubnormal; }

/// What is known of |v32 − v64| for one value: an absolute bound, and a relative one
/// (|v32 − v64| ≤ relative·|v64|) where the value stays away from 0 — the one that survives
/// exp, products and logarithms (bear.vm's sums of exponentials: an absolute bound carried
/// through exp over a whole box grows with e^max, a relative one stays a few ulps).
struct Error {
    double absolute = 0.0;
    double relative = kInf;
};

/// A relative bound is kept only while the value stays well inside float32's normal range.
constexpr double kRelativeFloor = 0x1p-100;

/// Rounding of a result in both formats, relative to it, with the propagated part `d` (the
/// small factors keep the bound above the products of rounding errors).
double grown(double d, double unit) { return (d + unit * (1 + d)) * (1 + 0x1p-40); }

/// Both bounds of one instruction's result from its operands' ranges and bounds: `absolute`
/// from the Lipschitz bound over the widened ranges, `relative` from the relative rules.
Error instruction_bound(const Instruction& ins, const Interval& out, const Interval* in, const Error* e) {
    const Interval& a = in[0];
    const Interval& b = in[1];
    const double ea = e[0].absolute, eb = e[1].absolute;
    const double ra = e[0].relative, rb = e[1].relative;
    const double m = magnitude(out);
    const double u = kFloat32Unit + kFloat64Unit, uf = kFloat32Function + kFloat64Function;
    Error r{kInf, kInf};
    switch (ins.op) {
    case Op::Neg:
    case Op::Abs:
        r = {ea, ra};
        break;
    case Op::Add:
    case Op::Sub: {
        const double d = ea + eb;
        r.absolute = d + rounded(m + d);
        // Operands of one sign (for sub: of opposite signs) add their magnitudes.
        const bool same = ins.op == Op::Add ? ((a.lo > 0 && b.lo > 0) || (a.hi < 0 && b.hi < 0))
                                            : ((a.lo > 0 && b.hi < 0) || (a.hi < 0 && b.lo > 0));
        if (same) r.relative = grown(std::max(ra, rb), u);
        break;
    }
    case Op::Mul: {
        const double d = magnitude(a) * eb + magnitude(b) * ea + ea * eb;
        r.absolute = d + rounded(m + d);
        r.relative = grown(ra + rb + ra * rb, u);
        break;
    }
    case Op::Square: {
        const double d = 2 * magnitude(a) * ea + ea * ea;
        r.absolute = d + rounded(m + d);
        r.relative = grown(2 * ra + ra * ra, u);
        break;
    }
    case Op::Div: {
        const double low = mignitude(b);
        const double widened = std::max(low - eb, rb < 0.5 ? low * (1 - rb) : 0.0);
        if (!(widened > 0)) return {kInf, kInf};
        const double d = ea / widened + magnitude(a) * eb / (low * widened);
        r.absolute = d + rounded(m + d);
        if (rb < 0.5) r.relative = grown((ra + rb) / (1 - rb), u);
        break;
    }
    case Op::Sqrt: {
        // |√x − √y| = |x − y| / (√x + √y) ≤ √|x − y|. A float32 operand below 0 gives NaN,
        // which every operation with a rule here carries to the root, where it is rechecked.
        if (a.lo < 0) return {kInf, kInf};
        const double root_sum = std::sqrt(std::max(a.lo - ea, 0.0)) + std::sqrt(a.lo);
        const double d = root_sum > 0 ? std::min(ea / root_sum, std::sqrt(ea)) : std::sqrt(ea);
        r.absolute = d + rounded(m + d);
        if (ra < 0.5) r.relative = grown(ra, u);  // |√(1 + δ) − 1| ≤ |δ|
        break;
    }
    case Op::Min:
    case Op::Max:
        r.absolute = std::max(ea, eb);
        if ((a.lo > 0 && b.lo > 0) || (a.hi < 0 && b.hi < 0)) r.relative = std::max(ra, rb);
        break;
    case Op::Hypot: {
        const double d = ea + eb;
        r.absolute = d + rounded_function(m + d);
        break;
    }
    case Op::Exp: {
        // e^(x + δ) = e^x · e^δ: relative, e^δ − 1 ≤ δ + δ² for δ ≤ 1 (no libm call: this
        // pass runs once per leaf over its whole tape).
        if (a.hi + ea > 80 || !(ea <= 1)) return {kInf, kInf};
        r.relative = grown(ea + ea * ea, uf);
        r.absolute = m * r.relative + kSubnormal;
        break;
    }
    case Op::Ln:
    case Op::Log2:
    case Op::Log10: {
        const double low = std::max(a.lo - ea, ra < 0.5 ? a.lo * (1 - ra) : 0.0);
        if (!(low > kRelativeFloor)) return {kInf, kInf};
        constexpr double kLog2e = 1.4426950408889634, kLog10e = 0.4342944819032518;
        const double scale = ins.op == Op::Ln ? 1.0 : ins.op == Op::Log2 ? kLog2e : kLog10e;
        // |ln(x(1 + δ)) − ln x| = |ln(1 + δ)| ≤ |δ| / (1 − |δ|).
        double d = scale * ea / low;
        if (ra < 0.5) d = std::min(d, scale * ra / (1 - ra));
        r.absolute = d + rounded_function(m + d);
        break;
    }
    case Op::Sin:
    case Op::Cos:
    case Op::Atan:
    case Op::Tanh:
        if (magnitude(a) + ea > 1e4) return {kInf, kInf};  // SLEEF's float accuracy holds well inside this
        r.absolute = ea + rounded_function(m + ea);
        break;
    case Op::Sinh:
    case Op::Cosh: {
        const double top = magnitude(a) + ea;
        if (top > 80 || !(ea <= 1)) return {kInf, kInf};
        const double d = std::cosh(top) * ea;  // rare: one libm call
        r.absolute = d + rounded_function(m + d);
        break;
    }
    case Op::Sign:
        r.absolute = (a.lo - ea > 0 || a.hi + ea < 0) ? 0.0 : kInf;
        break;
    case Op::Floor:
    case Op::Ceil:
        r.absolute = std::floor(a.lo - ea) == std::floor(a.hi + ea) && std::ceil(a.lo - ea) == std::ceil(a.hi + ea)
                         ? 0.0
                         : kInf;
        break;
    case Op::RAnd:
    case Op::ROr: {
        const double alpha = ins.imm;
        if (alpha == 1.0) {  // min / max
            r.absolute = std::max(ea, eb);
            break;
        }
        // The float32 kernel rounds 2α and 1 + α to float: only exactly representable ones.
        if (!(std::abs(alpha) < 1) || double(float(2.0 * alpha)) != 2.0 * alpha ||
            double(float(1.0 + alpha)) != 1.0 + alpha)
            return {kInf, kInf};
        // ∂/∂a, ∂/∂b ∈ [0, 2/(1 + α)] (interval.cpp); the formula's own rounding: a few units
        // of |a| + |b| before the square root, whose argument is ≥ (1 − |α|)(a² + b²).
        const double d = 2 / (1 + alpha) * (ea + eb);
        const double operands = magnitude(a) + magnitude(b) + ea + eb;
        r.absolute = d + 32 * u * operands / std::sqrt(1 - std::abs(alpha)) + rounded(m + d);
        break;
    }
    default:
        return {kInf, kInf};  // pow, tan, asin, acos, atan2, mod, select: no rule here
    }
    // Each bound tightens the other where the value stays away from 0.
    const double low = mignitude(out);
    if (low > kRelativeFloor && r.relative < 0.5) r.absolute = std::min(r.absolute, r.relative * m * (1 + 0x1p-40));
    else r.relative = kInf;
    if (low > kRelativeFloor) r.relative = std::min(r.relative, r.absolute / low * (1 + 0x1p-40));
    return r;
}

/// The ops whose float32 lane kernels compute the same function as float64 on float32
/// operands, rounded once (correctly, or by SLEEF within 2 ulps), at every argument, ±inf
/// included: for these the interval rules bound the float32 value too.
bool float32_range_rule(const Instruction& ins) {
    switch (ins.op) {
    case Op::Neg: case Op::Abs: case Op::Add: case Op::Sub: case Op::Mul: case Op::Square: case Op::Div:
    case Op::Sqrt: case Op::Min: case Op::Max: case Op::Exp: case Op::Ln: case Op::Log2: case Op::Log10:
        return true;
    case Op::RAnd:
    case Op::ROr:
        return ins.imm == 1.0;
    default:
        return false;
    }
}

/// A range of float32 results widened by one rounding (2 ulps, and float32's subnormal
/// range); beyond 1e38 it may overflow to ±inf.
Interval float32_rounded(Interval r) {
    constexpr double kWiden = kFloat32Function + 0x1p-40;
    r.lo = r.lo - std::abs(r.lo) * kWiden - kSubnormal;
    r.hi = r.hi + std::abs(r.hi) * kWiden + kSubnormal;
    if (r.lo < -1e38) r.lo = -kInf;
    if (r.hi > 1e38) r.hi = kInf;
    return r;
}

/// The range of a float32 value within `error` of a float64 value in `range`, rounded outward.
Interval within(const Interval& range, double error) {
    const double widen = error + (std::abs(range.lo) + std::abs(range.hi)) * 0x1p-50;
    return {range.lo - widen, range.hi + widen, false};
}

}  // namespace

double float32_error_bound(const Tape& tape, const std::vector<Interval>& ranges, std::vector<double>& errors) {
    auto usable = [](const Interval& r) { return !r.maybe_nan && !r.unknown() && magnitude(r) < kFloat32Safe; };
    // A value rounded to float32 once: half an ulp, relative where it is a normal number.
    auto rounded_once = [](const Interval& r) {
        const double low = mignitude(r);
        return Error{kFloat32Unit * magnitude(r), low > kRelativeFloor ? kFloat32Unit : kInf};
    };
    // `errors` holds the absolute bounds; the relative ones ride in its second quarter. A slot
    // whose absolute bound is +inf is loose: the range of its float32 values rides in the third
    // and fourth quarters (NaN there: not even that is known).
    const std::size_t n = tape.slot_count;
    if (!tape.inputs.empty()) return kInf;   // values from elsewhere: nothing known of them
    if (errors.size() < n * 4) errors.resize(n * 4);
    std::fill_n(errors.begin(), n * 2, kInf);   // the ranges are written before they are read
    auto get = [&errors, n](uint32_t slot) { return Error{errors[slot], errors[n + slot]}; };
    auto set = [&errors, n](uint32_t slot, Error e) {
        errors[slot] = e.absolute;
        errors[n + slot] = e.relative;
    };
    auto set_loose = [&errors, n](uint32_t slot, const Interval& range32) {
        errors[slot] = kInf;
        errors[n + slot] = kInf;
        const bool known = !range32.maybe_nan;
        errors[2 * n + slot] = known ? range32.lo : std::numeric_limits<double>::quiet_NaN();
        errors[3 * n + slot] = known ? range32.hi : std::numeric_limits<double>::quiet_NaN();
    };
    auto loose_range = [&errors, n](uint32_t slot) {
        const double lo = errors[2 * n + slot];
        return std::isnan(lo) ? kUnknownInterval : Interval{lo, errors[3 * n + slot], false};
    };
    for (auto [slot, axis] : tape.arguments) {
        if (!usable(ranges[slot])) return kInf;
        set(slot, rounded_once(ranges[slot]));
    }
    for (auto [slot, value] : tape.constants) {
        if (!(std::abs(value) < kFloat32Safe)) return kInf;
        set(slot, rounded_once({value, value, false}));
    }
    for (const Instruction& ins : tape.code) {
        const Interval& out = ranges[ins.out];
        if (out.maybe_nan) return kInf;
        Interval in[ir::kMaxArity] = {};
        Error e[ir::kMaxArity] = {};
        bool loose = false;   // an operand without a finite bound (so its range may be infinite)
        const int arity = std::min(ir::op_arity(ins.op), int(ir::kMaxArity));
        for (int k = 0; k < arity; ++k) {
            if ((ins.constant_operands >> k) & 1u) {
                in[k] = {ins.constant[k], ins.constant[k], false};
                if (!(std::abs(ins.constant[k]) < kFloat32Safe)) return kInf;
                e[k] = rounded_once(in[k]);
            } else {
                in[k] = ranges[ins.in[k]];
                e[k] = get(ins.in[k]);
                loose = loose || !(e[k].absolute < kInf);
            }
        }
        const bool out_usable = usable(out);
        if (!loose && out_usable) {
            const Error bound = instruction_bound(ins, out, in, e);
            if (bound.absolute < kFloat32Safe) {
                set(ins.out, bound);
                continue;
            }
        }
        // The float32 value's own range, from its operands' float32 ranges.
        if (!float32_range_rule(ins)) {
            set_loose(ins.out, kUnknownInterval);
            continue;
        }
        Interval range32[ir::kMaxArity] = {};
        for (int k = 0; k < arity; ++k) {
            const bool slot_operand = !((ins.constant_operands >> k) & 1u);
            range32[k] = slot_operand && !(e[k].absolute < kInf) ? loose_range(ins.in[k]) : within(in[k], e[k].absolute);
        }
        const Interval result32 = float32_rounded(interval_op(ins.op, range32[0], range32[1], range32[2], ins.imm));
        if (out_usable && result32.bounded() && !result32.maybe_nan) {
            // Both values lie in the hull of the two ranges.
            const double width = (std::max(out.hi, result32.hi) - std::min(out.lo, result32.lo)) * (1 + 0x1p-40);
            if (width < kFloat32Safe) {
                const double low = mignitude(out);
                set(ins.out, {width, low > kRelativeFloor ? width / low * (1 + 0x1p-40) : kInf});
                continue;
            }
        }
        set_loose(ins.out, result32);
    }
    return errors[tape.root_slot];
}

}  // namespace fortu
