// tests/unit/interp_vector_math_test.cpp — SLEEF's float32 vector kernels (vector_math.def)
// against libm over each op's argument sweep, within the ULP bound the list states, on every
// ISA this CPU has (tails and constant operands included); the voxel engine's float32 lanes
// use them; and the README's accuracy table is the one the list gives.
#include "interp/vector_math.hpp"
#include "interp/voxel_engine.hpp"
#include "interp_test_support.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace fortu;

namespace {

struct VectorOp {
    ir::Op op;
    const char* sleef;
    const char* accuracy;
    double ulp;
    double lo, hi;
    int arity;
    double (*reference)(double, double);
};

const std::vector<VectorOp>& vector_ops() {
    static const std::vector<VectorOp> ops = {
#define FORTU_VECTOR_MATH_1(op, sleef, accuracy, ulp, lo, hi) \
    {ir::Op::op, #sleef, #accuracy, ulp, lo, hi, 1, [](double a, double) { return std::sleef(a); }},
#define FORTU_VECTOR_MATH_2(op, sleef, accuracy, ulp, lo, hi) \
    {ir::Op::op, #sleef, #accuracy, ulp, lo, hi, 2, [](double a, double b) { return std::sleef(a, b); }},
#include "interp/vector_math.def"
    };
    return ops;
}

/// |got − exact| in float32 ULPs of the exact value; 0 when both are the same NaN/inf
/// class, infinity when only one of them is.
double ulp_error(float got, double exact) {
    if (std::isnan(exact) || std::isnan(got)) return std::isnan(exact) && std::isnan(got) ? 0.0 : INFINITY;
    const float rounded = static_cast<float>(exact);
    if (std::isinf(rounded) || std::isinf(got)) return got == rounded ? 0.0 : INFINITY;
    int exponent = 0;
    std::frexp(exact, &exponent);
    const double ulp = std::ldexp(1.0, std::max(exponent - 24, -149));
    return std::fabs(static_cast<double>(got) - exact) / ulp;
}

const std::vector<float> kSpecials = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, INFINITY, -INFINITY, NAN};

/// The sweep's first operands and second operands (a grid for two-operand ops).
void sweep(const VectorOp& v, std::vector<float>& a, std::vector<float>& b) {
    a.clear();
    b.clear();
    if (v.arity == 1) {
        const int n = 20001;   // not a multiple of 8 or 16: the tail runs too
        for (int i = 0; i < n; ++i) a.push_back(static_cast<float>(v.lo + (v.hi - v.lo) * i / (n - 1)));
        a.insert(a.end(), kSpecials.begin(), kSpecials.end());
        b.assign(a.size(), 0.0f);
        return;
    }
    std::vector<float> axis;
    const int n = 301;
    for (int i = 0; i < n; ++i) axis.push_back(static_cast<float>(v.lo + (v.hi - v.lo) * i / (n - 1)));
    axis.insert(axis.end(), kSpecials.begin(), kSpecials.end());
    for (float x : axis)
        for (float y : axis) { a.push_back(x); b.push_back(y); }
}

std::vector<vector_math::Isa> isas_here() {
    std::vector<vector_math::Isa> isas;
    if (vector_math::best_isa() >= vector_math::Isa::avx2) isas.push_back(vector_math::Isa::avx2);
    if (vector_math::best_isa() >= vector_math::Isa::avx512) isas.push_back(vector_math::Isa::avx512);
    return isas;
}

bool same_bits(float x, float y) { return std::memcmp(&x, &y, sizeof x) == 0; }

}  // namespace

TEST_CASE("every vector kernel is within its stated ULP of libm over its sweep, on every ISA here") {
    REQUIRE_FALSE(isas_here().empty());   // fortu's x86-64 builds need AVX2 + FMA
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        for (const VectorOp& v : vector_ops()) {
            CAPTURE(std::string(vector_math::isa_name(isa)));
            CAPTURE(std::string(v.sleef));
            REQUIRE(vector_math::has_vector_kernel(v.op));
            std::vector<float> a, b;
            sweep(v, a, b);
            std::vector<float> out(a.size(), -7.0f);
            REQUIRE(vector_math::run_float(v.op, a.data(), b.data(), 0.0f, 0.0f, 0, out.data(),
                                           static_cast<int>(a.size())));
            double worst = 0.0;
            float worst_a = 0.0f, worst_b = 0.0f;
            for (std::size_t i = 0; i < a.size(); ++i) {
                const double e = ulp_error(out[i], v.reference(a[i], b[i]));
                if (e > worst) { worst = e; worst_a = a[i]; worst_b = b[i]; }
            }
            MESSAGE(fmt::format("{} {}: worst {:.4f} ULP at ({}, {})", vector_math::isa_name(isa), v.sleef, worst,
                                worst_a, worst_b));
            CHECK(worst <= v.ulp);
        }
    }
    vector_math::use_isa(vector_math::Isa::avx512);
}

TEST_CASE("constant operands and short tails give the same lanes as the arrays they stand for") {
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        CAPTURE(std::string(vector_math::isa_name(isa)));
        std::vector<float> x(37), k(37, 1.75f);
        for (int i = 0; i < 37; ++i) x[i] = 0.1f * static_cast<float>(i) - 1.3f;
        std::vector<float> both(37), a_const(37), b_const(37), tail(37, 99.0f);
        REQUIRE(vector_math::run_float(ir::Op::Pow, k.data(), x.data(), 0, 0, 0, both.data(), 37));
        REQUIRE(vector_math::run_float(ir::Op::Pow, nullptr, x.data(), 1.75f, 0, 1, a_const.data(), 37));
        REQUIRE(vector_math::run_float(ir::Op::Atan2, x.data(), k.data(), 0, 0, 0, b_const.data(), 37));
        std::vector<float> atan2_const(37);
        REQUIRE(vector_math::run_float(ir::Op::Atan2, x.data(), nullptr, 0, 1.75f, 2, atan2_const.data(), 37));
        REQUIRE(vector_math::run_float(ir::Op::Exp, x.data(), nullptr, 0, 0, 0, tail.data(), 5));
        for (int i = 0; i < 37; ++i) {
            CHECK(same_bits(both[i], a_const[i]));
            CHECK(same_bits(b_const[i], atan2_const[i]));
        }
        for (int i = 0; i < 5; ++i) CHECK(tail[i] == doctest::Approx(std::exp(x[i])).epsilon(1e-6));
        for (int i = 5; i < 37; ++i) CHECK(tail[i] == 99.0f);   // nothing written past the lanes
    }
    vector_math::use_isa(vector_math::Isa::avx512);
}

TEST_CASE("sinh and cosh overflow a little early, as the README says: inf beyond |x| = 88.72") {
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        const float x[3] = {88.7f, 89.0f, -89.0f};
        float s[3], c[3];
        REQUIRE(vector_math::run_float(ir::Op::Sinh, x, nullptr, 0, 0, 0, s, 3));
        REQUIRE(vector_math::run_float(ir::Op::Cosh, x, nullptr, 0, 0, 0, c, 3));
        CHECK(std::isfinite(s[0]));
        CHECK(std::isfinite(c[0]));
        CHECK(s[1] == INFINITY);   // exact: 2.24e38, below FLT_MAX (3.40e38)
        CHECK(c[1] == INFINITY);
        CHECK(s[2] == -INFINITY);
        CHECK(c[2] == INFINITY);
    }
    vector_math::use_isa(vector_math::Isa::avx512);
}

TEST_CASE("operations without a vector kernel, or no vector ISA, are left to the lane loop") {
    float a[4] = {1, 2, 3, 4}, out[4] = {0, 0, 0, 0};
    CHECK_FALSE(vector_math::has_vector_kernel(ir::Op::Add));
    CHECK_FALSE(vector_math::run_float(ir::Op::Add, a, a, 0, 0, 0, out, 4));
    vector_math::use_isa(vector_math::Isa::none);
    CHECK(vector_math::active_isa() == vector_math::Isa::none);
    CHECK_FALSE(vector_math::run_float(ir::Op::Exp, a, nullptr, 0, 0, 0, out, 4));
    CHECK(out[0] == 0.0f);
    vector_math::use_isa(vector_math::Isa::avx512);
    CHECK(vector_math::active_isa() == vector_math::best_isa());
}

TEST_CASE("AVX2 and AVX-512 give bit-identical float32 values (on CPUs with both)") {
    if (vector_math::best_isa() < vector_math::Isa::avx512) return;   // nothing to compare here
    for (const VectorOp& v : vector_ops()) {
        CAPTURE(std::string(v.sleef));
        std::vector<float> a, b;
        sweep(v, a, b);
        std::vector<float> narrow(a.size()), wide(a.size());
        vector_math::use_isa(vector_math::Isa::avx2);
        vector_math::run_float(v.op, a.data(), b.data(), 0, 0, 0, narrow.data(), static_cast<int>(a.size()));
        vector_math::use_isa(vector_math::Isa::avx512);
        vector_math::run_float(v.op, a.data(), b.data(), 0, 0, 0, wide.data(), static_cast<int>(a.size()));
        std::size_t differing = 0;
        for (std::size_t i = 0; i < a.size(); ++i) differing += !same_bits(narrow[i], wide[i]);
        CHECK(differing == 0);
    }
}

TEST_CASE("the README's float32 accuracy table is the one vector_math.def gives") {
    std::ostringstream table;
    table << "| operation | SLEEF function (AVX2 / AVX-512) | error bound, float32 | tested over |\n"
          << "|---|---|---|---|\n";
    for (const VectorOp& v : vector_ops()) {
        std::ostringstream range;
        range << "[" << v.lo << ", " << v.hi << "]" << (v.arity == 2 ? "²" : "");
        table << "| " << ir::op_name(v.op) << " | Sleef_" << v.sleef << "f8_" << v.accuracy << "avx2 / Sleef_"
              << v.sleef << "f16_" << v.accuracy << "avx512f | " << v.ulp << " ULP | " << range.str() << " |\n";
    }
    std::ifstream in(std::string(FORTU_SOURCE_DIR) + "/README.md");
    std::stringstream readme;
    readme << in.rdbuf();
    INFO("expected in README.md:\n", table.str());
    CHECK(readme.str().find(table.str()) != std::string::npos);
}
