// tests/unit/interp_float32_bound_test.cpp — the bound on |float32 − float64| that lets the
// sign renderer's leaves run in float32: it must hold at every point of the box (checked on
// the shipped models' tapes over many boxes, point by point), be +inf where no rule applies,
// and be the exact figure on a hand-computed case.
#include "interp_test_support.hpp"

#include "interp/box_simplify.hpp"
#include "interp/float32_bound.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <vector>

using namespace fortu;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Tape ssa_tape(const Model& model) { return compile_tape(model.graph, TapeSpec{{model.root}, {}, {}, false}); }

double bound_over(const Tape& tape, const std::array<Interval, 3>& box) {
    std::vector<Interval> ranges;
    std::vector<double> errors;
    evaluate_intervals(tape, box, ranges);
    return float32_error_bound(tape, ranges, errors);
}

/// The largest |v32 − v64| over `points` random points of the box divided by the bound (≤ 1
/// when the bound holds), and whether the bound was finite; points whose float32 value is
/// NaN are the renderer's to recheck and do not count.
struct Check {
    double worst_ratio = 0.0;
    bool finite = false;
};

template <class T>
std::vector<T> run(const Tape& tape, const std::vector<std::array<double, 3>>& points) {
    const int n = static_cast<int>(points.size());
    std::vector<T> lanes(std::size_t(tape.slot_count) * n);
    std::vector<T*> slots(tape.slot_count);
    for (uint32_t s = 0; s < tape.slot_count; ++s) slots[s] = lanes.data() + std::size_t(s) * n;
    for (auto [slot, axis] : tape.arguments)
        for (int l = 0; l < n; ++l) slots[slot][l] = T(points[l][axis]);
    for (auto [slot, value] : tape.constants) std::fill_n(slots[slot], n, T(value));
    run_lanes<T, 0>(tape.code.data(), tape.code.size(), slots.data(), n);
    return std::vector<T>(slots[tape.root_slot], slots[tape.root_slot] + n);
}

Check check_box(const Tape& tape, const std::array<Interval, 3>& box, std::mt19937_64& random, int points) {
    Check c;
    const double bound = bound_over(tape, box);
    if (!(bound < kInf)) return c;
    c.finite = true;
    std::vector<std::array<double, 3>> at(points);
    for (auto& p : at)
        for (int a = 0; a < 3; ++a) p[a] = std::uniform_real_distribution<double>(box[a].lo, box[a].hi)(random);
    const std::vector<float> v32 = run<float>(tape, at);
    const std::vector<double> v64 = run<double>(tape, at);
    for (int l = 0; l < points; ++l) {
        if (std::isnan(v32[l])) continue;
        c.worst_ratio = std::max(c.worst_ratio, std::abs(double(v32[l]) - v64[l]) / bound);
    }
    return c;
}

std::optional<Model> load_vm(const std::string& name) {
    std::string error;
    auto source = SourceFile::load((std::filesystem::path(FORTU_SHARED_DIR) / "data" / name).string(), error);
    REQUIRE_MESSAGE(source, error);
    DiagnosticSink sink;
    return import_vm(source, sink);
}

double bound_of_text(const char* text, const std::array<Interval, 3>& box) {
    auto c = test::compile_text(text);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    return bound_over(ssa_tape(*c.model), box);
}

}  // namespace

TEST_CASE("float32 bound: a hand-computed case") {
    // −X over X in [1, 2]: X rounds to float32 within 2^-24 · 2; negation is exact.
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN -X\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Tape tape = ssa_tape(*c.model);
    CHECK(bound_over(tape, {Interval{1, 2, false}, Interval{0, 0, false}, Interval{}}) == 0x1p-23);
}

TEST_CASE("float32 bound: +inf without a rule, near a pole or where NaN may occur") {
    const std::array<Interval, 3> box{Interval{0.5, 1, false}, Interval{0.5, 1, false}, Interval{}};
    const std::array<Interval, 3> across_zero{Interval{-1, 1, false}, Interval{0.5, 1, false}, Interval{}};
    auto bound_of = [](const char* text, const std::array<Interval, 3>& b) {
        auto c = test::compile_text(text);
        REQUIRE_MESSAGE(c.model, c.sink.render_all());
        return bound_over(ssa_tape(*c.model), b);
    };
    CHECK(bound_of("ARGUMENT X, Y\nRETURN X^Y - 0.7\n", box) == kInf);          // pow: no rule
    CHECK(bound_of("ARGUMENT X, Y\nRETURN TAN(X) - Y\n", box) == kInf);         // tan: no rule
    CHECK(bound_of("ARGUMENT X, Y\nRETURN 1 / X - Y\n", across_zero) == kInf);  // a pole in the box
    CHECK(bound_of("ARGUMENT X, Y\nRETURN SQRT(X) - Y\n", across_zero) == kInf);  // NaN where X < 0
    CHECK(bound_of("ARGUMENT X, Y\nRETURN LN(X) - Y\n", across_zero) == kInf);
    CHECK(bound_of("ARGUMENT X, Y\nRETURN 1 / X - Y\n", box) < 1e-5);
    CHECK(bound_of("ARGUMENT X, Y\nRETURN LN(X) + EXP(Y) - SQRT(X*X + Y*Y)\n", box) < 1e-5);
}

TEST_CASE("float32 bound: a pole whose contribution vanishes (bear.vm's exp(−30.6·max(…, |0.1/x|)))") {
    // 0.1/X over X in [−1, 1] is [−∞, ∞] in both formats, and so is the float32 error of every
    // value up to the exp; the exp's result lies in [0, e^−15] in both, so its error is at most
    // e^−15 (3.06e-7) and a little; + Y − 0.75 adds float32's rounding of Y, 0.75 and the sums.
    const std::array<Interval, 3> across_zero{Interval{-1, 1, false}, Interval{0.5, 1, false}, Interval{}};
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN EXP(-30 * MAX(0.5, ABS(0.1 / X))) + Y - 0.75\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Tape tape = ssa_tape(*c.model);
    const double bound = bound_over(tape, across_zero);
    CHECK(bound > std::exp(-15.0));
    CHECK(bound < 1e-6);
    std::mt19937_64 random(7);
    const Check check = check_box(tape, across_zero, random, 4096);
    CHECK(check.finite);
    CHECK(check.worst_ratio <= 1.0);
    // The pole itself: X = 0 gives ±inf in both formats, and exp(−∞) = 0.
    const std::vector<std::array<double, 3>> at{{0.0, 0.75, 0.0}, {-0.0, 0.75, 0.0}};
    CHECK(run<float>(tape, at) == std::vector<float>{0.0f, 0.0f});
    CHECK(run<double>(tape, at) == std::vector<double>{0.0, 0.0});
    // Where the exp's range is not small the bound is finite but too large to help.
    const std::array<Interval, 3> wide{Interval{-1, 1, false}, Interval{0.5, 1, false}, Interval{}};
    CHECK(bound_of_text("ARGUMENT X, Y\nRETURN EXP(-MAX(0, ABS(0.1 / X))) - Y\n", wide) > 0.9);
}

TEST_CASE("float32 bound holds point by point on the shipped models' tapes") {
    // Boxes of every size the renderer visits (halves of the domain down to a few nodes of a
    // 1024 grid), placed at random; 64 random points each, float32 against float64.
    std::mt19937_64 random(12345);
    for (const char* name : {"prospero.vm", "bear.vm", "tanglecube.vm", "quarter.vm", "colonnade.vm", "hi.vm"}) {
        CAPTURE(name);
        const std::optional<Model> model = load_vm(name);
        REQUIRE(model);
        const Tape tape = ssa_tape(*model);
        const bool three = model->dims() == 3;
        int finite = 0;
        double worst = 0.0;
        for (int trial = 0; trial < 300; ++trial) {
            const double size = std::ldexp(1.0, -int(trial % 10));
            std::array<Interval, 3> box{Interval{}, Interval{}, Interval{}};
            for (int a = 0; a < (three ? 3 : 2); ++a) {
                const double lo = std::uniform_real_distribution<double>(-1, 1 - size)(random);
                box[a] = {lo, lo + size, false};
            }
            const Check c = check_box(tape, box, random, 64);
            finite += c.finite;
            worst = std::max(worst, c.worst_ratio);
        }
        CHECK(worst <= 1.0);
        CHECK(finite > 0);  // the bound is not vacuous: some boxes run in float32
    }
}
