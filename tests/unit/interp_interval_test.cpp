// tests/unit/interp_interval_test.cpp — interval arithmetic: exact bounds on simple cases,
// and the contract (every point value the kernels compute lies inside) on random boxes for
// every operation.
#include "interp/interval.hpp"

#include "interp/ir/ir.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

using namespace fortu;
using ir::Op;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();

bool same(const Interval& a, const Interval& b) {
    return a.lo == b.lo && a.hi == b.hi && a.maybe_nan == b.maybe_nan;
}

/// A value of the range: its ends first, then 0 and −0 where it holds them, then random
/// points (of every magnitude where an end is infinite).
double sample(const Interval& r, int p, std::mt19937_64& rng) {
    if (p == 0) return r.lo;
    if (p == 1) return r.hi;
    if (p == 2 && r.lo <= 0 && r.hi >= 0) return 0.0;
    if (p == 3 && r.lo <= 0 && r.hi >= 0) return -0.0;
    std::uniform_real_distribution<double> unit(0, 1);
    double v;
    if (r.bounded()) {
        v = r.lo + unit(rng) * (r.hi - r.lo);
    } else {
        const double finite_end = r.lo > -kInf ? r.lo : r.hi < kInf ? r.hi : 0.0;
        const double step = std::exp(std::uniform_real_distribution<double>(-5, 700)(rng));
        v = rng() % 2 ? finite_end + step : finite_end - step;
    }
    return std::min(std::max(v, r.lo), r.hi);
}

}  // namespace

TEST_CASE("interval bounds of the exact operations") {
    const Interval a{-1, 2, false}, b{3, 4, false};
    CHECK(same(interval_op(Op::Add, a, b, a, 0), {2, 6, false}));
    CHECK(same(interval_op(Op::Sub, a, b, a, 0), {-5, -1, false}));
    CHECK(same(interval_op(Op::Mul, a, b, a, 0), {-4, 8, false}));
    CHECK(same(interval_op(Op::Square, a, a, a, 0), {0, 4, false}));
    CHECK(same(interval_op(Op::Abs, a, a, a, 0), {0, 2, false}));
    CHECK(same(interval_op(Op::Min, a, b, a, 0), {-1, 2, false}));
    CHECK(same(interval_op(Op::Max, a, b, a, 0), {3, 4, false}));
    CHECK(same(interval_op(Op::Neg, a, a, a, 0), {-2, 1, false}));
    CHECK(same(interval_op(Op::Sqrt, a, a, a, 0), {0, std::sqrt(2.0), true}));  // NaN left of 0
    CHECK(same(interval_op(Op::Div, b, a, a, 0), {-kInf, kInf, false}));         // a contains 0: a pole, no NaN
    CHECK(same(interval_op(Op::Div, a, b, a, 0), {-1.0 / 3, 2.0 / 3, false}));
    CHECK(same(interval_op(Op::Select, b, a, b, 0), a));
    CHECK(same(interval_op(Op::Select, {-2, 0, false}, a, b, 0), b));
    CHECK(same(interval_op(Op::Select, a, a, b, 0), {-1, 4, false}));
    CHECK(same(interval_op(Op::Add, kUnknownInterval, b, a, 0), kUnknownInterval));
    CHECK(same(interval_op(Op::Mul, {1e300, 1e300, false}, {1e300, 1e300, false}, a, 0), {kInf, kInf, false}));  // overflow
}

TEST_CASE("R-operations: monotone, decided signs") {
    const Interval pos{0.5, 1, false}, neg{-2, -1, false}, both{-1, 1, false};
    CHECK(interval_op(Op::RAnd, pos, pos, pos, 0.0).positive());
    CHECK(interval_op(Op::RAnd, neg, both, pos, 0.0).negative());
    CHECK(interval_op(Op::ROr, pos, both, pos, 0.0).positive());
    CHECK(interval_op(Op::ROr, neg, neg, pos, 0.5).negative());
    const Interval r = interval_op(Op::RAnd, pos, both, pos, 0.0);
    CHECK(r.lo < 0);
    CHECK(r.hi > 0);
    CHECK(same(interval_op(Op::RAnd, pos, both, pos, 1.0), {-1, 1, false}));  // MINMAX: exact
}

TEST_CASE("whole powers") {
    const Interval sq = interval_op(Op::Pow, {-1, 2, false}, {2, 2, false}, {}, 0);
    CHECK(sq.lo == 0);
    CHECK(sq.hi >= 4);
    CHECK(sq.hi < 4 + 1e-12);
    const Interval cube = interval_op(Op::Pow, {-2, 1, false}, {3, 3, false}, {}, 0);
    CHECK(cube.lo <= -8);
    CHECK(cube.lo > -8 - 1e-12);
    CHECK(interval_op(Op::Pow, {-1, 2, false}, {-2, -2, false}, {}, 0).unknown());  // 1/0 inside
}

TEST_CASE("sin and cos find their extrema inside the box") {
    const Interval r = interval_op(Op::Sin, {1.0, 2.0, false}, {}, {}, 0);
    CHECK(r.hi == 1.0);
    CHECK(r.lo <= std::sin(1.0));
    CHECK(r.lo > 0.84);
    const Interval c = interval_op(Op::Cos, {3.0, 3.5, false}, {}, {}, 0);
    CHECK(c.lo == -1.0);
    CHECK(c.hi >= std::cos(3.5));
    CHECK(c.hi < -0.9);
}

TEST_CASE("every operation: point values lie inside the interval (random boxes)") {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> centre(-4, 4), width(0, 3), unit(0, 1);
    for (int op_index = 0; op_index < ir::kOpCount; ++op_index) {
        const Op op = static_cast<Op>(op_index);
        if (ir::op_flags(op) & ir::kLeaf) continue;
        CAPTURE(ir::op_name(op));
        const double imm = (op == Op::RAnd || op == Op::ROr) ? std::vector<double>{0.0, 1.0, 0.5, -0.5}[rng() % 4] : 0.0;
        for (int trial = 0; trial < 400; ++trial) {
            Interval box[3];
            for (Interval& i : box) {
                const double m = centre(rng), w = trial % 5 == 0 ? 0.0 : width(rng);
                i = {m - w, m + w, false};
                // Infinite bounds (a pole upstream), and ranges that are one infinity.
                const unsigned kind = rng() % 12;
                if (kind == 0) i.lo = -kInf;
                if (kind == 1) i.hi = kInf;
                if (kind == 2) i = {-kInf, kInf, false};
                if (kind == 3) i = rng() % 2 ? Interval{kInf, kInf, false} : Interval{-kInf, -kInf, false};
                if (kind == 4) i = {0.0, 0.0, false};
            }
            if (op == Op::Pow && trial % 2) box[1] = {double(trial % 7) - 3, double(trial % 7) - 3, false};
            const Interval r = interval_op(op, box[0], box[1], box[2], imm);
            for (int p = 0; p < 40; ++p) {
                double v[3];
                for (int k = 0; k < 3; ++k) v[k] = sample(box[k], p, rng);
                const double value = ir::fold(op, v[0], v[1], v[2], imm);
                if (std::isnan(value)) {
                    CHECK(r.maybe_nan);
                } else {
                    CHECK(r.lo <= value);
                    CHECK(value <= r.hi);
                }
            }
        }
    }
}

TEST_CASE("ops.def's sign_operands: which operands pass only their sign") {
    CHECK(ir::passes_sign(Op::Neg, 0));
    CHECK(ir::passes_sign(Op::Min, 0));
    CHECK(ir::passes_sign(Op::Max, 1));
    CHECK(ir::passes_sign(Op::RAnd, 1));
    CHECK(ir::passes_sign(Op::ROr, 0));
    CHECK_FALSE(ir::passes_sign(Op::Select, 0));  // SELECT(c, a, b): c's value decides
    CHECK(ir::passes_sign(Op::Select, 1));
    CHECK(ir::passes_sign(Op::Select, 2));
    CHECK_FALSE(ir::passes_sign(Op::Add, 0));
    CHECK_FALSE(ir::passes_sign(Op::Mul, 1));
    CHECK_FALSE(ir::passes_sign(Op::Sqrt, 0));
}

TEST_CASE("ops without an interval rule are unknown, never a guess") {
    const Interval a{0.1, 0.2, false};
    CHECK(same(interval_op(Op::Tan, a, a, a, 0), kUnknownInterval));   // ops.def: not_bounded()
    CHECK(same(interval_op(Op::Atan2, a, a, a, 0), kUnknownInterval));
    CHECK(same(interval_op(Op::Mod, a, a, a, 0), kUnknownInterval));
    // A rule named in ops.def (increasing: widened by 8 ulps each way).
    const Interval e = interval_op(Op::Exp, {0, 1, false}, a, a, 0);
    CHECK(e.lo == 1 - 8 * std::numeric_limits<double>::epsilon());
    CHECK(e.hi == std::exp(1.0) + std::exp(1.0) * 8 * std::numeric_limits<double>::epsilon());
}

TEST_CASE("infinite bounds: a pole, and what survives it") {
    const Interval pole = interval_op(Op::Div, {0.1, 0.1, false}, {-1, 2, false}, {}, 0);
    CHECK(same(pole, {-kInf, kInf, false}));   // 0.1/x: ±inf at x = ±0, never NaN
    CHECK_FALSE(pole.unknown());
    CHECK_FALSE(pole.bounded());
    CHECK(kUnknownInterval.unknown());
    CHECK(same(interval_op(Op::Neg, pole, {}, {}, 0), pole));
    CHECK(same(interval_op(Op::Abs, pole, {}, {}, 0), {0, kInf, false}));
    CHECK(same(interval_op(Op::Square, pole, {}, {}, 0), {0, kInf, false}));
    // max(−x, x) of independent ranges: the rule does not know they are one value.
    CHECK(same(interval_op(Op::Max, interval_op(Op::Neg, pole, {}, {}, 0), pole, {}, 0), pole));
    const Interval at_least = interval_op(Op::Max, {0.5, 1, false}, pole, {}, 0);
    CHECK(same(at_least, {0.5, kInf, false}));
    const Interval scaled = interval_op(Op::Mul, {-30.6, -30.6, false}, at_least, {}, 0);
    CHECK(same(scaled, {-kInf, -15.3, false}));
    CHECK(same(interval_op(Op::Mul, at_least, {2, 2, false}, {}, 0), {1, kInf, false}));
    // exp(−∞) = 0: exp of [−∞, 3] is [0, e^3], widened by 8 ulps.
    CHECK(same(interval_op(Op::Exp, {-kInf, 3, false}, {}, {}, 0), {0, std::exp(3.0) + std::exp(3.0) * 8 * kEps, false}));
    CHECK(interval_op(Op::Exp, scaled, {}, {}, 0).positive() == false);   // exp may underflow to 0
    CHECK(interval_op(Op::Add, interval_op(Op::Exp, scaled, {}, {}, 0), {1, 2, false}, {}, 0).positive());
}

TEST_CASE("infinite bounds: ∞ − ∞, 0·∞, ∞/∞ and 0/0 may be NaN, nothing else") {
    const Interval up{1, kInf, false}, down{-kInf, -1, false}, pole{-kInf, kInf, false};
    CHECK(same(interval_op(Op::Add, up, {1, 2, false}, {}, 0), {2, kInf, false}));
    CHECK(same(interval_op(Op::Add, up, down, {}, 0), {-kInf, kInf, true}));    // ∞ + (−∞)
    CHECK(same(interval_op(Op::Sub, up, up, {}, 0), {-kInf, kInf, true}));      // ∞ − ∞
    CHECK(same(interval_op(Op::Sub, up, down, {}, 0), {2, kInf, false}));
    CHECK(same(interval_op(Op::Add, {kInf, kInf, false}, pole, {}, 0), {-kInf, kInf, true}));
    CHECK(same(interval_op(Op::Mul, {0, 1, false}, up, {}, 0), {0, kInf, true}));    // 0·∞
    CHECK(same(interval_op(Op::Mul, {1, 2, false}, up, {}, 0), {1, kInf, false}));
    CHECK(same(interval_op(Op::Mul, {-1, 2, false}, down, {}, 0), {-kInf, kInf, true}));
    CHECK(same(interval_op(Op::Mul, {0, 0, false}, {1, 2, false}, {}, 0), {0, 0, false}));
    CHECK(same(interval_op(Op::Div, {0, 1, false}, {-1, 2, false}, {}, 0), {-kInf, kInf, true}));  // 0/0
    CHECK(same(interval_op(Op::Div, {0, 0, false}, {-1, 2, false}, {}, 0), {0, 0, true}));
    CHECK(same(interval_op(Op::Div, up, up, {}, 0), {0, kInf, true}));           // ∞/∞
    CHECK(same(interval_op(Op::Div, {1, 2, false}, up, {}, 0), {0, 2, false}));
    CHECK(same(interval_op(Op::Div, down, {2, 4, false}, {}, 0), {-kInf, -0.25, false}));
    CHECK(same(interval_op(Op::Sqrt, {4, kInf, false}, {}, {}, 0), {2, kInf, false}));
    CHECK(same(interval_op(Op::Ln, {0, 1, false}, {}, {}, 0), {-kInf, 0, false}));   // ln(0) = −∞
    CHECK(same(interval_op(Op::Ln, {-1, 1, false}, {}, {}, 0), kUnknownInterval));
    CHECK(same(interval_op(Op::Sin, up, {}, {}, 0), {-1, 1, true}));             // sin(∞) is NaN
    CHECK(same(interval_op(Op::Floor, pole, {}, {}, 0), pole));
    CHECK(same(interval_op(Op::Min, up, {2, 3, false}, {}, 0), {1, 3, false}));
    CHECK(same(interval_op(Op::RAnd, up, {2, 3, false}, {}, 1.0), {1, 3, false}));   // MINMAX: exact
    CHECK(same(interval_op(Op::RAnd, up, {2, 3, false}, {}, 0.0), kUnknownInterval));  // ∞ − ∞ in R0
    CHECK(same(interval_op(Op::Pow, up, {2, 2, false}, {}, 0), kUnknownInterval));
    const Interval a = interval_op(Op::Atan, pole, {}, {}, 0);
    CHECK(a.lo <= -std::numbers::pi / 2);
    CHECK(a.lo > -1.5708);
    CHECK_FALSE(a.maybe_nan);
    CHECK(same(interval_op(Op::Exp, {710, 720, false}, {}, {}, 0), {std::numeric_limits<double>::max(), kInf, false}));
}
