// tests/unit/interp_float_gradient_test.cpp — float32 lane gradients (float_gradient.hpp)
// against ir::Dual in float64 on the same tape, for every derivative rule the shaded view
// relies on, and the operations without a rule.
#include "interp_test_support.hpp"

#include "interp/float_gradient.hpp"
#include "interp/ir/dual.hpp"
#include "interp/lane_kernel.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace fortu;

namespace {

struct Point {
    double x, y, z;
};

/// The largest difference between the float32 lanes' value and gradient and ir::Dual's, each
/// relative to the larger of 1 and the exact number's size.
double largest_error(const std::string& text, const std::vector<Point>& points, const CompileOptions& options = {}) {
    test::Compiled c = test::compile_text(text, options);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Tape tape = compile_tape(c.model->graph, c.model->root);
    REQUIRE(float_gradient_supported(tape));
    const int n = static_cast<int>(points.size());
    std::vector<float> coords(3 * std::size_t(n)), value(n), grad(3 * std::size_t(n));
    for (int i = 0; i < n; ++i)
        coords[i] = float(points[i].x), coords[n + i] = float(points[i].y), coords[2 * n + i] = float(points[i].z);
    FloatGradientScratch scratch;
    float_gradients(tape, {coords.data(), coords.data() + n, coords.data() + 2 * n}, n, value.data(),
                    {grad.data(), grad.data() + n, grad.data() + 2 * n}, scratch);
    // ir::Dual at the same (float-rounded) points.
    std::vector<ir::Dual> duals(std::size_t(tape.slot_count) * n, ir::Dual(0.0));
    std::vector<ir::Dual*> slots(tape.slot_count);
    for (std::size_t k = 0; k < tape.slot_count; ++k) slots[k] = duals.data() + k * n;
    for (auto [slot, axis] : tape.arguments)
        for (int i = 0; i < n; ++i) slots[slot][i] = ir::Dual::variable(coords[axis * n + i], axis);
    for (auto [slot, constant] : tape.constants)
        for (int i = 0; i < n; ++i) slots[slot][i] = ir::Dual(constant);
    run_lanes<ir::Dual, 0>(tape.code.data(), tape.code.size(), slots.data(), n);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
        const ir::Dual& exact = slots[tape.root_slot][i];
        const double got[4] = {value[i], grad[i], grad[n + i], grad[2 * n + i]};
        const double want[4] = {exact.v, exact.d[0], exact.d[1], exact.d[2]};
        for (int k = 0; k < 4; ++k) {
            CAPTURE(i);
            CAPTURE(k);
            REQUIRE(std::isfinite(want[k]));
            worst = std::max(worst, std::abs(got[k] - want[k]) / std::max(1.0, std::abs(want[k])));
        }
    }
    return worst;
}

const std::vector<Point> kPoints{{0.3, -0.7, 0.45}, {-0.55, 0.2, -0.35}, {0.8, 0.65, -0.15}, {-0.25, -0.4, 0.9},
                                 {0.05, 0.5, 0.6}};

}  // namespace

TEST_CASE("float32 lane gradients agree with ir::Dual to float32 rounding") {
    const char* models[] = {
        // arithmetic
        "ARGUMENT X, Y, Z\nRETURN X*Y - Z/(X + 2) + (-Y) + X^2 - 3*Z\n",
        // transcendentals (SLEEF's exp, ln, sin, cos) and roots
        "ARGUMENT X, Y, Z\nRETURN EXP(-2*X*Y) + LN(2 + Z) + SIN(3*X) * COS(2*Y) + SQRT(1 + Z*Z) + ABS(X - Y)\n",
        "ARGUMENT X, Y, Z\nRETURN TAN(X) + ATAN(Y) + ASIN(Z/2) + ACOS(X/2) + SINH(Y) * COSH(Z) + TANH(X + Y)\n",
        "ARGUMENT X, Y, Z\nRETURN LOG10(3 + X) + LOG2(3 + Y) + ATAN(Y, X + 2) + MOD(5*X + 7, 2) + (2 + Z)^(1 + X) + HYPOT(X, Y + 1)\n",
        // branches: MIN, MAX, SELECT, and the R-operations (R0, R-alpha, minmax)
        "ARGUMENT X, Y, Z\nRETURN MIN(X, Y) - MAX(Y*Z, X) + SELECT(X - Y, Z, X*Y) + SIGN(Z) + FLOOR(X)\n",
        "ARGUMENT X, Y, Z\nRETURN ((0.5 - X*X) & (0.4 - Y*Y)) | (0.3 - Z*Z)\n",
    };
    for (const char* text : models) {
        CAPTURE(text);
        CHECK(largest_error(text, kPoints) < 2e-5);
    }
    for (const char* rsystem : {"alpha=0.5", "minmax"}) {
        CAPTURE(rsystem);
        CompileOptions options;
        options.rsystem = parse_rsystem(rsystem);
        REQUIRE(options.rsystem);
        CHECK(largest_error("ARGUMENT X, Y, Z\nRETURN ((0.5 - X*X) & (0.4 - Y*Y)) | (0.3 - Z*Z)\n", kPoints, options) <
              2e-5);
    }
}

TEST_CASE("float32 lane gradients: the ops without a rule are reported") {
    test::Compiled arg = test::compile_text("ARGUMENT X, Y, Z\nRETURN X - Y * Z\n");
    REQUIRE(arg.model);
    Tape tape = compile_tape(arg.model->graph, arg.model->root);
    CHECK(float_gradient_supported(tape));
    tape.code.front().op = ir::Op::Arg;   // a leaf the tape never holds: no rule
    CHECK_FALSE(float_gradient_supported(tape));
}
