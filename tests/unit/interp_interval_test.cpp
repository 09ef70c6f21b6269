// tests/unit/interp_interval_test.cpp — interval arithmetic: exact bounds on simple cases,
// and the contract (every point value the kernels compute lies inside) on random boxes for
// every operation.
#include "interp/interval.hpp"

#include "interp/ir/ir.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>

using namespace fortu;
using ir::Op;

namespace {

bool same(const Interval& a, const Interval& b) {
    return a.lo == b.lo && a.hi == b.hi && a.maybe_nan == b.maybe_nan;
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
    CHECK(same(interval_op(Op::Div, b, a, a, 0), kUnknownInterval));             // a contains 0
    CHECK(same(interval_op(Op::Div, a, b, a, 0), {-1.0 / 3, 2.0 / 3, false}));
    CHECK(same(interval_op(Op::Select, b, a, b, 0), a));
    CHECK(same(interval_op(Op::Select, {-2, 0, false}, a, b, 0), b));
    CHECK(same(interval_op(Op::Select, a, a, b, 0), {-1, 4, false}));
    CHECK(same(interval_op(Op::Add, kUnknownInterval, b, a, 0), kUnknownInterval));
    CHECK(same(interval_op(Op::Mul, {1e300, 1e300, false}, {1e300, 1e300, false}, a, 0), kUnknownInterval));
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
            }
            if (op == Op::Pow && trial % 2) box[1] = {double(trial % 7) - 3, double(trial % 7) - 3, false};
            const Interval r = interval_op(op, box[0], box[1], box[2], imm);
            for (int p = 0; p < 40; ++p) {
                double v[3];
                for (int k = 0; k < 3; ++k) {
                    const double t = p == 0 ? 0.0 : p == 1 ? 1.0 : unit(rng);
                    v[k] = box[k].lo + t * (box[k].hi - box[k].lo);
                    v[k] = std::min(std::max(v[k], box[k].lo), box[k].hi);
                }
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
