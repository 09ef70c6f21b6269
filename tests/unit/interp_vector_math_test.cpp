// tests/unit/interp_vector_math_test.cpp — the float32 vector kernels (vector_math.def: SLEEF's
// and fortu's own) against libm over each op's argument sweep and near its special points,
// within the ULP bound the list states, on every ISA this CPU has (tails and constant
// operands included); fortu's exp and ln on their special values exactly; the compiled
// tapes' one-vector functions give the lane loops' bits; and the README's accuracy table is
// the one the list gives.
#include "interp/vector_math.hpp"
#include "interp/voxel_engine.hpp"
#include "interp_test_support.hpp"

#include <doctest/doctest.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__AVX2__)
#include <immintrin.h>
#endif
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

using namespace fortu;

namespace {

struct VectorOp {
    ir::Op op;
    const char* name;
    const char* library;
    const char* accuracy;
    double ulp;
    double lo, hi;
    int arity;
    double (*reference)(double, double);
};

const std::vector<VectorOp>& vector_ops() {
    static const std::vector<VectorOp> ops = {
#define FORTU_VECTOR_MATH_1(op, name, library, accuracy, ulp, lo, hi) \
    {ir::Op::op, #name, #library, #accuracy, ulp, lo, hi, 1, [](double a, double) { return std::name(a); }},
#define FORTU_VECTOR_MATH_2(op, name, library, accuracy, ulp, lo, hi) \
    {ir::Op::op, #name, #library, #accuracy, ulp, lo, hi, 2, [](double a, double b) { return std::name(a, b); }},
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

/// Where one-operand ops are hard, beyond the even sweep: exp near 0, its switch to the wide
/// path (|x| = 87), the overflow threshold ln(FLT_MAX), the lowest normal result, the
/// subnormal results and the last nonzero one; the logarithms near 1, √½ and √2 (where the
/// mantissa's range wraps), the smallest normal and the subnormals, and FLT_MAX.
std::vector<float> hard_points(ir::Op op) {
    std::vector<float> centres;
    const bool logarithm = op == ir::Op::Ln || op == ir::Op::Log10 || op == ir::Op::Log2;
    if (op == ir::Op::Exp)
        centres = {0.0f, 1e-30f, -1e-30f, 87.0f, -87.0f, 88.7228394f, -87.3365479f, -95.0f, -100.0f,
                   -103.278931f, -103.972076f, -104.0f, 89.0f};
    else if (logarithm)
        centres = {1.0f, 0.70710677f, 1.41421354f, 1.17549435e-38f, 1e-40f, 1e-45f, 3.40282347e38f};
    std::vector<float> points;
    for (float c : centres) {
        float below = c, above = c;
        for (int k = 0; k < 300; ++k) {   // the 300 floats on either side
            points.push_back(below);
            points.push_back(above);
            below = std::nextafter(below, -INFINITY);
            above = std::nextafter(above, INFINITY);
        }
    }
    if (logarithm)   // every binade, subnormals included, 64 mantissas each
        for (int e = -149; e <= 127; ++e)
            for (int j = 0; j < 64; ++j) points.push_back(std::ldexp(1.0f + j / 64.0f, e));
    return points;
}

/// The sweep's first operands and second operands (a grid for two-operand ops).
void sweep(const VectorOp& v, std::vector<float>& a, std::vector<float>& b) {
    a.clear();
    b.clear();
    if (v.arity == 1) {
        const int n = 20001;   // not a multiple of 8 or 16: the tail runs too
        for (int i = 0; i < n; ++i) a.push_back(static_cast<float>(v.lo + (v.hi - v.lo) * i / (n - 1)));
        a.insert(a.end(), kSpecials.begin(), kSpecials.end());
        const std::vector<float> hard = hard_points(v.op);
        a.insert(a.end(), hard.begin(), hard.end());
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
            CAPTURE(std::string(v.name));
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
            MESSAGE(fmt::format("{} {}: worst {:.4f} ULP at ({}, {})", vector_math::isa_name(isa), v.name, worst,
                                worst_a, worst_b));
            CHECK(worst <= v.ulp);
        }
    }
    vector_math::use_isa(vector_math::Isa::avx512);
}

TEST_CASE("sin and cos from one sincos: within Sin's and Cos's ULP of libm over their sweep, the same on every ISA") {
    const VectorOp* sin_op = nullptr;
    const VectorOp* cos_op = nullptr;
    for (const VectorOp& v : vector_ops()) {
        if (v.op == ir::Op::Sin) sin_op = &v;
        if (v.op == ir::Op::Cos) cos_op = &v;
    }
    REQUIRE(sin_op);
    REQUIRE(cos_op);
    std::vector<float> a, unused;
    sweep(*sin_op, a, unused);
    const int n = static_cast<int>(a.size());
    std::vector<std::vector<float>> sines, cosines;
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        CAPTURE(std::string(vector_math::isa_name(isa)));
        std::vector<float> s(n + 3, -7.0f), c(n + 3, -7.0f);
        REQUIRE(vector_math::run_float_sincos(a.data(), s.data(), c.data(), n));
        double worst_sin = 0.0, worst_cos = 0.0;
        for (int i = 0; i < n; ++i) {
            worst_sin = std::max(worst_sin, ulp_error(s[i], std::sin(double(a[i]))));
            worst_cos = std::max(worst_cos, ulp_error(c[i], std::cos(double(a[i]))));
        }
        MESSAGE(fmt::format("{} sincos: worst {:.4f} ULP (sin), {:.4f} ULP (cos)", vector_math::isa_name(isa), worst_sin,
                            worst_cos));
        CHECK(worst_sin <= sin_op->ulp);
        CHECK(worst_cos <= cos_op->ulp);
        for (int i = n; i < n + 3; ++i) CHECK((s[i] == -7.0f && c[i] == -7.0f));   // nothing past the lanes
        sines.push_back(s);
        cosines.push_back(c);
    }
    std::size_t differing = 0;
    for (std::size_t k = 1; k < sines.size(); ++k)
        for (int i = 0; i < n; ++i) {
            const auto differ = [](float x, float y) { return !(std::isnan(x) && std::isnan(y)) && !same_bits(x, y); };
            differing += differ(sines[0][i], sines[k][i]) + differ(cosines[0][i], cosines[k][i]);
        }
    CHECK(differing == 0);
    vector_math::use_isa(vector_math::Isa::none);
    float x = 1.0f, s = 0.0f, c = 0.0f;
    CHECK_FALSE(vector_math::run_float_sincos(&x, &s, &c, 1));
    CHECK(s == 0.0f);
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

/// op over `x` through run_float on the active ISA.
std::vector<float> run_all(ir::Op op, const std::vector<float>& x) {
    std::vector<float> out(x.size(), -7.0f);
    REQUIRE(vector_math::run_float(op, x.data(), nullptr, 0, 0, 0, out.data(), static_cast<int>(x.size())));
    return out;
}

TEST_CASE("fortu's exp gives IEEE's special values, overflows at ln(FLT_MAX) and rounds subnormal results") {
    const float kLastFinite = 88.7228317f;   // 0x42b17217, just below ln(FLT_MAX) = 88.72283905
    const float kFirstInfinite = 88.7228394f;   // 0x42b17218
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        CAPTURE(std::string(vector_math::isa_name(isa)));
        const std::vector<float> x = {NAN, INFINITY, -INFINITY, 0.0f, -0.0f, kLastFinite, kFirstInfinite, 89.0f,
                                      1e30f, -87.3365479f, -100.0f, -103.278931f, -104.0f, -1e30f, 1.0f};
        const std::vector<float> y = run_all(ir::Op::Exp, x);
        CHECK(std::isnan(y[0]));
        CHECK(y[1] == INFINITY);
        CHECK(same_bits(y[2], 0.0f));
        CHECK(y[3] == 1.0f);
        CHECK(y[4] == 1.0f);
        CHECK(y[5] == 3.40279851e38f);   // the correctly rounded e^x: 3.4027985e38
        CHECK(y[6] == INFINITY);
        CHECK(y[7] == INFINITY);
        CHECK(y[8] == INFINITY);
        CHECK(y[9] == 1.1754907e-38f);   // just below FLT_MIN (1.1754944e-38): subnormal, correctly rounded
        CHECK(y[10] == 3.7835059e-44f);   // 27 · 2^-149 (e^-100 = 3.72e-44)
        CHECK(y[11] == 1.40129846e-45f);   // 2^-149, the last nonzero
        CHECK(same_bits(y[12], 0.0f));
        CHECK(same_bits(y[13], 0.0f));
        CHECK(y[14] == 2.71828175f);
    }
    vector_math::use_isa(vector_math::Isa::avx512);
}

TEST_CASE("fortu's ln gives IEEE's special values and is exact at 1 and right on subnormals") {
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        CAPTURE(std::string(vector_math::isa_name(isa)));
        const std::vector<float> x = {NAN, INFINITY, -INFINITY, 0.0f, -0.0f, -1.0f, -1e-45f, 1.0f,
                                      1.40129846e-45f, 1e-40f, 1.17549435e-38f, 3.40282347e38f, 2.0f};
        const std::vector<float> y = run_all(ir::Op::Ln, x);
        CHECK(std::isnan(y[0]));
        CHECK(y[1] == INFINITY);
        CHECK(std::isnan(y[2]));
        CHECK(y[3] == -INFINITY);
        CHECK(y[4] == -INFINITY);
        CHECK(std::isnan(y[5]));
        CHECK(std::isnan(y[6]));
        CHECK(same_bits(y[7], 0.0f));
        CHECK(y[8] == -103.278931f);   // ln 2^-149
        CHECK(y[9] == -92.10341f);   // correctly rounded (−92.1034091…)
        CHECK(y[10] == -87.3365479f);
        CHECK(y[11] == 88.7228394f);
        CHECK(y[12] == 0.693147182f);
    }
    vector_math::use_isa(vector_math::Isa::avx512);
}

#if defined(__AVX2__)
namespace {

/// One vector of 8 (AVX2) or 16 (AVX-512) lanes through a one-vector function.
void call_8(void* function, const float* in, float* out) {
    _mm256_storeu_ps(out, reinterpret_cast<__m256 (*)(__m256)>(function)(_mm256_loadu_ps(in)));
}
__attribute__((target("avx512f"))) void call_16(void* function, const float* in, float* out) {
    _mm512_storeu_ps(out, reinterpret_cast<__m512 (*)(__m512)>(function)(_mm512_loadu_ps(in)));
}

}  // namespace

TEST_CASE("the compiled tapes' one-vector functions give the lane loops' bits, AVX2 and AVX-512") {
    for (vector_math::Isa isa : isas_here()) {
        vector_math::use_isa(isa);
        CAPTURE(std::string(vector_math::isa_name(isa)));
        const int width = isa == vector_math::Isa::avx512 ? 16 : 8;
        for (const VectorOp& v : vector_ops()) {
            if (v.arity != 1) continue;
            CAPTURE(std::string(v.name));
            std::vector<float> a, b;
            sweep(v, a, b);
            a.resize(a.size() / 16 * 16);
            const std::vector<float> lanes = run_all(v.op, a);
            void* function = vector_math::one_vector_function(isa, v.op);
            REQUIRE(function != nullptr);
            std::size_t differing = 0;
            for (std::size_t i = 0; i < a.size(); i += width) {
                float out[16];
                if (width == 16) call_16(function, a.data() + i, out);
                else call_8(function, a.data() + i, out);
                for (int l = 0; l < width; ++l) differing += !same_bits(out[l], lanes[i + l]);
            }
            CHECK(differing == 0);
        }
        CHECK(vector_math::one_vector_function(isa, ir::Op::Add) == nullptr);
    }
    CHECK(vector_math::one_vector_function(vector_math::Isa::none, ir::Op::Exp) == nullptr);
    vector_math::use_isa(vector_math::Isa::avx512);
}
#endif

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

// SLEEF's AVX-512 logarithms give -NaN where the AVX2 ones give NaN (negative arguments): a NaN
// is a NaN to every consumer of a field, so only its sign and payload may differ.
TEST_CASE("AVX2 and AVX-512 give bit-identical float32 values, NaNs aside (on CPUs with both)") {
    if (vector_math::best_isa() < vector_math::Isa::avx512) return;   // nothing to compare here
    for (const VectorOp& v : vector_ops()) {
        CAPTURE(std::string(v.name));
        std::vector<float> a, b;
        sweep(v, a, b);
        std::vector<float> narrow(a.size()), wide(a.size());
        vector_math::use_isa(vector_math::Isa::avx2);
        vector_math::run_float(v.op, a.data(), b.data(), 0, 0, 0, narrow.data(), static_cast<int>(a.size()));
        vector_math::use_isa(vector_math::Isa::avx512);
        vector_math::run_float(v.op, a.data(), b.data(), 0, 0, 0, wide.data(), static_cast<int>(a.size()));
        std::size_t differing = 0, nans = 0;
        for (std::size_t i = 0; i < a.size(); ++i) {
            const bool both_nan = std::isnan(narrow[i]) && std::isnan(wide[i]);
            nans += both_nan;
            differing += !both_nan && !same_bits(narrow[i], wide[i]);
        }
        CHECK(differing == 0);
        if (v.op == ir::Op::Log10) CHECK(nans > 0);   // the sweep does reach the NaNs
    }
}

TEST_CASE("the README's float32 accuracy table is the one vector_math.def gives") {
    std::ostringstream table;
    table << "| operation | function (AVX2 / AVX-512) | error bound, float32 | tested over |\n"
          << "|---|---|---|---|\n";
    for (const VectorOp& v : vector_ops()) {
        std::ostringstream range, function;
        range << "[" << v.lo << ", " << v.hi << "]" << (v.arity == 2 ? "²" : "");
        if (std::string(v.library) == "fortu")
            function << "fortu's own (8 / 16 lanes)";
        else
            function << "Sleef_" << v.name << "f8_" << v.accuracy << "avx2 / Sleef_" << v.name << "f16_" << v.accuracy
                     << "avx512f";
        table << "| " << ir::op_name(v.op) << " | " << function.str() << " | " << v.ulp << " ULP | " << range.str()
              << " |\n";
    }
    std::ifstream in(std::string(FORTU_SOURCE_DIR) + "/README.md");
    std::stringstream readme;
    readme << in.rdbuf();
    INFO("expected in README.md:\n", table.str());
    CHECK(readme.str().find(table.str()) != std::string::npos);
}
