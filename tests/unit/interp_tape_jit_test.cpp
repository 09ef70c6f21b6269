// Compiled tapes give the lane kernel's values bit for bit (NaN where it gives NaN): every operation, with each operand
// a slot or a constant, R-operations of every α, NaN, ±0, ±inf and subnormal arguments, chains
// whose results stay in registers, tails shorter than a chunk, and constants changed between
// runs (the voxel engine's per-row values).
#include "interp/constant_divisor.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/tape.hpp"
#include "interp/tape_jit.hpp"
#include "interp/vector_math.hpp"
#include "interp/voxel_engine.hpp"
#include "interp_test_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace fortu;
using ir::Op;

namespace {

/// Arguments that find differences: special values first, then random ones of all magnitudes.
template <class T>
std::vector<T> argument_values(int axis, int lanes) {
    const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
    const T special[] = {T(0),  T(-0.0), T(1),   T(-1),  inf, -inf, nan, -nan, std::numeric_limits<T>::denorm_min(),
                         T(0.5), T(-2.5), T(1e-30), T(3e30), T(2), T(-0.75), T(100)};
    constexpr int kSpecial = sizeof(special) / sizeof(special[0]);
    std::mt19937 random(1234 + axis);
    std::uniform_real_distribution<double> mantissa(-1, 1);
    std::uniform_int_distribution<int> exponent(-8, 8);
    std::vector<T> values(lanes);
    for (int l = 0; l < lanes; ++l) {
        // Every pair of special values meets in some lane: axis 0 varies fastest.
        const int k = axis == 0 ? l % kSpecial : axis == 1 ? (l / kSpecial) % kSpecial : (l / 7) % kSpecial;
        values[l] = l < kSpecial * kSpecial ? special[k] : T(std::ldexp(mantissa(random), exponent(random)));
    }
    return values;
}

/// Each axis's values over the lanes; argument_values() where none are given.
template <class T>
using Arguments = std::vector<std::vector<T>>;

/// The tape's outputs over `lanes` points, by the lane kernel or by the compiled tape.
template <class T>
std::vector<std::vector<T>> run(const Tape& tape, const std::vector<Instruction>& code, int lanes, bool compiled,
                                const CompiledTape<T>* jit = nullptr, JitScratch<T>* scratch = nullptr,
                                const Arguments<T>* arguments = nullptr) {
    std::vector<std::vector<T>> storage(tape.slot_count, std::vector<T>(lanes, T(0)));
    for (auto [slot, value] : tape.constants) std::fill(storage[slot].begin(), storage[slot].end(), T(value));
    for (auto [slot, axis] : tape.arguments)
        storage[slot] = arguments ? (*arguments)[axis] : argument_values<T>(axis, lanes);
    std::vector<T*> slots(tape.slot_count);
    for (uint32_t s = 0; s < tape.slot_count; ++s) slots[s] = storage[s].data();
    if (compiled) jit->run(code.data(), code.size(), slots.data(), lanes, *scratch, true);
    else run_lanes<T, 0>(code.data(), code.size(), slots.data(), lanes);
    std::vector<std::vector<T>> outputs;
    for (uint32_t slot : tape.outputs) outputs.push_back(storage[slot]);
    return outputs;
}

/// The same value bit for bit, or both NaN: which NaN (its sign, its payload) an operation on
/// two NaNs gives depends on its operands' order, which compilers may swap (the sanitizer
/// build's lane loops gave -NaN where the release build's gave NaN), so no two builds promise it.
template <class T>
bool same_value(T a, T b) {
    return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
bool same_values(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t l = 0; l < a.size(); ++l)
        if (!same_value(a[l], b[l])) return false;
    return true;
}

template <class T>
bool same_outputs(const std::vector<std::vector<T>>& a, const std::vector<std::vector<T>>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
        if (!same_values(a[k], b[k])) return false;
    return true;
}

/// The compiled tape's outputs, checked against the lane kernel's bit for bit; returned.
template <class T>
std::vector<std::vector<T>> check_same(const Tape& tape, int lanes, const std::vector<Instruction>* other_code = nullptr,
                                       const Arguments<T>* arguments = nullptr) {
    std::unique_ptr<CompiledTape<T>> jit = CompiledTape<T>::compile(tape);
    REQUIRE(jit);
    CHECK(jit->width() == tape_jit_width());
    CHECK(jit->chunk_lanes() == (tape_jit_width() == JitWidth::avx512 ? 64 : 32) * 4 / int(sizeof(T)));
    JitScratch<T> scratch;
    const std::vector<Instruction>& code = other_code ? *other_code : tape.code;
    const auto expected = run<T>(tape, code, lanes, false, nullptr, nullptr, arguments);
    const auto actual = run<T>(tape, code, lanes, true, jit.get(), &scratch, arguments);
    REQUIRE(actual.size() == expected.size());
    int differing = 0;
    // The instruction that computes each output, to name it.
    const auto producer = [&](std::size_t k) {
        for (auto ins = code.rbegin(); ins != code.rend(); ++ins)
            if (ins->out == tape.outputs[k])
                return std::string(ir::op_name(ins->op)) + " constants " + std::to_string(ins->constant_operands) +
                       " imm " + std::to_string(ins->imm);
        return std::string("input");
    };
    for (std::size_t k = 0; k < expected.size(); ++k)
        for (int l = 0; l < lanes; ++l)
            if (!same_value(actual[k][l], expected[k][l]) && ++differing <= 5)
                MESSAGE(std::string(sizeof(T) == 4 ? "float32" : "float64"), " output ", k, " (", producer(k), ") lane ", l,
                        ": compiled ", double(actual[k][l]), ", lane kernel ", double(expected[k][l]));
    CHECK(differing == 0);
    return actual;
}

/// Runs `body` in each way compiled tapes run on this CPU: AVX2 code with the AVX2 lane loops
/// (which it calls for SLEEF's functions), AVX2 code with the AVX-512 lane loops (handed back
/// to them: AMD's Zen 4 until its AVX-512 code was measured faster), and AVX-512 code with the
/// AVX-512 lane loops.
template <class F>
void at_each_width(F body) {
    const JitWidth chosen_width = tape_jit_width();
    const vector_math::Isa chosen_isa = vector_math::active_isa();
    std::vector<std::pair<JitWidth, vector_math::Isa>> ways{{JitWidth::avx2, vector_math::Isa::avx2}};
    if (vector_math::best_isa() == vector_math::Isa::avx512) ways.push_back({JitWidth::avx2, vector_math::Isa::avx512});
    if (tape_jit_avx512_available() && vector_math::best_isa() == vector_math::Isa::avx512)
        ways.push_back({JitWidth::avx512, vector_math::Isa::avx512});
    for (auto [width, isa] : ways) {
        use_tape_jit_width(width);
        vector_math::use_isa(isa);
        INFO("compiled tapes ", jit_width_name(width), ", lane loops' transcendentals ", vector_math::isa_name(isa));
        body();
    }
    use_tape_jit_width(chosen_width);
    vector_math::use_isa(chosen_isa);
}

/// Every operation with each operand a slot or a constant (R-operations with α 0, 0.5, -0.3 and
/// 1), each also fed by the one before it so that operands come from the registers.
ir::Graph every_operation(std::vector<ir::NodeId>& outputs) {
    ir::Graph g;
    const ir::NodeId x = g.argument(0), y = g.argument(1), z = g.argument(2);
    const ir::NodeId c = g.constant(0.75), d = g.constant(-2.5);
    ir::NodeId previous = x;
    for (int o = 0; o < ir::kOpCount; ++o) {
        const Op op = static_cast<Op>(o);
        const int arity = ir::op_arity(op);
        if (arity == 0) continue;
        const bool r_operation = op == Op::RAnd || op == Op::ROr;
        for (double alpha : r_operation ? std::vector<double>{0.0, 0.5, -0.3, 1.0} : std::vector<double>{0.0}) {
            std::vector<std::array<ir::NodeId, 3>> operand_sets;
            if (arity == 1) operand_sets = {{x, 0, 0}, {previous, 0, 0}};
            if (arity == 2) operand_sets = {{x, y, 0}, {c, y, 0}, {x, d, 0}, {previous, z, 0}, {z, previous, 0}};
            if (arity == 3)
                operand_sets = {{x, y, z}, {x, c, z}, {x, y, d}, {previous, y, z}, {z, previous, x}, {y, x, previous}};
            for (const auto& operands : operand_sets) {
                const ir::NodeId n = g.make(op, std::span(operands.data(), arity), alpha);
                if (g.is_constant(n) || std::find(outputs.begin(), outputs.end(), n) != outputs.end()) continue;
                outputs.push_back(n);
                previous = n;
            }
        }
    }
    return g;
}

}  // namespace

TEST_CASE("compiled tapes: every operation, operand kind and special value as the lane kernel") {
    if (!tape_jit_available()) {
        MESSAGE("no AVX2 on this CPU: compiled tapes are not used");
        return;
    }
    at_each_width([&] {
        std::vector<ir::NodeId> outputs;
        const ir::Graph g = every_operation(outputs);
        const Tape tape = compile_tape(g, TapeSpec{outputs, {}, {}});
        // The outputs keep their slots to the end: to see results forwarded in registers and never
        // stored, the same operations as one chain whose only output is its end.
        std::vector<ir::NodeId> chain_outputs;
        const ir::Graph chain_graph = every_operation(chain_outputs);
        const Tape chain = compile_tape(chain_graph, TapeSpec{{chain_outputs.back()}, {}, {}});
        for (int lanes : {1024, 1000, 256 + 16, 64 + 63, 63, 17, 1}) {
            CAPTURE(lanes);
            check_same<float>(tape, lanes);
            check_same<double>(tape, lanes);
            check_same<float>(chain, lanes);
            check_same<double>(chain, lanes);
        }
    });
}

TEST_CASE("compiled tapes read constants changed between runs, as the per-row values are") {
    if (!tape_jit_available()) return;
    at_each_width([&] {
        auto c = test::compile_text("ARGUMENT X, Y;\nRETURN MAX(X * 0.5 - Y, SQRT(X * X + 3) & (Y - 1.25)) / 7;\n");
        REQUIRE(c.model);
        const Tape tape = compile_tape(c.model->graph, c.model->root);
        std::unique_ptr<CompiledTape<double>> jit = CompiledTape<double>::compile(tape);
        REQUIRE(jit);
        JitScratch<double> scratch;
        std::vector<Instruction> code = tape.code;
        int changed = 0;
        for (Instruction& ins : code)
            for (int k = 0; k < ir::kMaxArity; ++k)
                if (ins.constant_operands & (1u << k)) ins.constant[k] = ins.constant[k] * 3 + 1, ++changed;
        REQUIRE(changed >= 4);
        // One scratch for both runs, as a worker keeps it from tile to tile.
        const auto first = run<double>(tape, tape.code, 512, true, jit.get(), &scratch);
        const auto second = run<double>(tape, code, 512, true, jit.get(), &scratch);
        CHECK(same_outputs(first, run<double>(tape, tape.code, 512, false)));
        CHECK(same_outputs(second, run<double>(tape, code, 512, false)));
        CHECK(!same_outputs(first, second));
    });
}

namespace {

/// A 2D grid of `cols` × `rows` nodes over [x0, x1] × [y0, y1].
Grid plane_grid(double x0, double x1, int cols, double y0, double y1, int rows) {
    Grid g;
    g.dims = 2;
    g.x = {x0, x1, cols};
    g.y = {y0, y1, rows};
    return g;
}

/// The field of `model` on `grid`, compiled (whatever the size) and through the lane loops.
std::pair<Field, Field> compiled_and_lanes(const Model& model, const Grid& grid, Precision precision) {
    const VoxelEngine compiled({.precision = precision, .compile_above_lane_operations = 0});
    const VoxelEngine lanes({.precision = precision, .compile = false});
    return {compiled.evaluate_grid(model.graph, model.root, grid, {}, {}),
            lanes.evaluate_grid(model.graph, model.root, grid, {}, {})};
}

}  // namespace

TEST_CASE("the voxel engine compiled and through its lane loops: the same field, bit for bit") {
    if (!tape_jit_available()) return;
    at_each_width([&] {
        // Compiled whatever the size: hoisted rows (per-row constants), a tail in every tile (1000
        // columns), transcendentals handed back to the lane kernel.
        const char* text = "ARGUMENT X, Y;\nA = EXP(-X * X) * COS(3 * Y) - 0.2;\nB = (0.8 - SQRT(X * X + Y * Y)) | (Y - X * X);\n"
                           "FOR I = 1, 40\n  A = (A & (B - I / 100)) | (0.3 - ABS(X - I / 40));\nEND FOR\nRETURN A;\n";
        auto c = test::compile_text(text);
        REQUIRE_MESSAGE(c.model, c.sink.render_all());
        const Grid plane = plane_grid(-1.5, 1.5, 1000, -1.2, 1.3, 600);
        Grid cube;   // 3D: tiles of whole rows, values per XY and XZ plane
        cube.dims = 3;
        cube.x = cube.y = cube.z = {-1.1, 1.2, 45};
        const char* solid = "ARGUMENT X, Y, Z;\nA = EXP(-X * X) * COS(3 * Y) - Z * Z;\n"
                            "FOR I = 1, 20\n  A = (A & (0.9 - SQRT(X * X + Y * Y + Z * Z) - I / 100)) | (0.3 - ABS(Z - I / 40));\n"
                            "END FOR\nRETURN A;\n";
        auto c3 = test::compile_text(solid);
        REQUIRE_MESSAGE(c3.model, c3.sink.render_all());
        for (const auto& [model, grid] : {std::pair{&*c.model, plane}, std::pair{&*c3.model, cube}}) {
            for (Precision precision : {Precision::Float64, Precision::Float32}) {
                CAPTURE(grid.dims);
                const auto [a, b] = compiled_and_lanes(*model, grid, precision);
                REQUIRE(a.values.size() == b.values.size());
                CHECK(same_values(a.values, b.values));
            }
        }
    });
}

TEST_CASE("compiled MIN, MAX and SELECT keep a NaN first operand where it can be one, and drop the check where not") {
    if (!tape_jit_available()) return;
    at_each_width([&] {
        // SQRT(X) is NaN for X < 0 (first operand of MAX and MIN there); SQRT(X*X + Y*Y) and Y - 0.5 are
        // never NaN (one-instruction MIN/MAX); the R-operations of α = 1 are MIN/MAX too.
        const char* text = "ARGUMENT X, Y;\nA = MAX(SQRT(X), Y - 0.5);\nB = MIN(SQRT(X * X + Y * Y) - 0.7, X - Y * Y);\n"
                           "C = MIN(SQRT(Y + 0.2), B);\nRETURN MAX(MAX(A, B) - 0.1, C);\n";
        auto c = test::compile_text(text);
        REQUIRE_MESSAGE(c.model, c.sink.render_all());
        const Grid plane = plane_grid(-1.5, 1.5, 300, -1.2, 1.3, 200);
        for (Precision precision : {Precision::Float64, Precision::Float32}) {
            CAPTURE(int(precision));
            const auto [a, b] = compiled_and_lanes(*c.model, plane, precision);
            CHECK(same_values(a.values, b.values));
            const auto nans = std::count_if(a.values.begin(), a.values.end(), [](double v) { return std::isnan(v); });
            CHECK(nans > 0);                              // the NaN cases are exercised
            CHECK(nans < std::ptrdiff_t(a.values.size()));
        }
    });
}

TEST_CASE("compiled tapes take the per-row values from the rows' arrays or from the patched code, alike") {
    if (!tape_jit_available()) return;
    at_each_width([&] {
        // 1536 columns: two tiles of 768 lanes a row, no tail, so compiled code reads the per-row
        // values (Y-only nodes) from their arrays; Y * Y as the second operand of a subtraction is
        // a negated pool entry. With ATAN2 (handed back to the lane kernel in float64), the code
        // is patched as for the lane loops.
        const Grid wide = plane_grid(-1.5, 1.5, 1536, -1.2, 1.3, 40);
        for (const char* text : {"ARGUMENT X, Y;\nRETURN MAX(X - Y * Y, 0.5 - Y) * MIN(X * X - COS(Y), Y + 0.25 - X);\n",
                                 "ARGUMENT X, Y;\nRETURN ATAN2(X + Y, Y * Y + 1) + MAX(X - Y * Y, 0.5 - Y);\n"}) {
            auto c = test::compile_text(text);
            REQUIRE_MESSAGE(c.model, c.sink.render_all());
            for (Precision precision : {Precision::Float64, Precision::Float32}) {
                CAPTURE(text);
                CAPTURE(int(precision));
                const auto [a, b] = compiled_and_lanes(*c.model, wide, precision);
                CHECK(same_values(a.values, b.values));
                CHECK(std::adjacent_find(a.values.begin(), a.values.end(), std::not_equal_to<>()) != a.values.end());
            }
        }
    });
}

TEST_CASE("compiled float32 exp and ln: their narrow path inline, chunks with a wide lane by the call, as the lane loops") {
    if (!tape_jit_available()) return;
    at_each_width([&] {
        ir::Graph g;
        const ir::NodeId x = g.argument(0), y = g.argument(1);
        const ir::NodeId ex = g.make(Op::Exp, std::array{x}), ln = g.make(Op::Ln, std::array{y});
        // Chained, so the functions also read held and stored results.
        const ir::NodeId both = g.make(Op::Ln, std::array{g.make(Op::Add, std::array{ex, ln})});
        const Tape tape = compile_tape(g, TapeSpec{{ex, ln, both}, {}, {}});
        constexpr int kLanes = 1024;
        // The first half only ordinary arguments (|x| ≤ 87 for exp, positive normal numbers for
        // ln): the narrow path. In the second half each 32-lane chunk has one lane of another
        // kind (overflow, underflow, NaN, ±inf, 0, negative, subnormal), at a different place.
        std::mt19937 random(7);
        std::uniform_real_distribution<float> exponent(-87.0f, 87.0f), magnitude(-37.0f, 38.0f);
        std::vector<float> xs(kLanes), ys(kLanes);
        for (int l = 0; l < kLanes; ++l) xs[l] = exponent(random), ys[l] = std::pow(10.0f, magnitude(random));
        const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
        const float wide_x[] = {89.5f, -95.0f, nan, inf, -inf, 104.0f, -150.0f, 87.5f};
        const float wide_y[] = {0.0f, -1.0f, nan, inf, -0.0f, 1e-40f, std::numeric_limits<float>::denorm_min(), -inf};
        for (int chunk = 16; chunk < 32; ++chunk) {
            const int lane = chunk * 32 + (chunk * 5) % 32;
            xs[lane] = wide_x[chunk % 8];
            ys[lane + (chunk % 2)] = wide_y[chunk % 8];
        }
        const Arguments<float> arguments{xs, ys, std::vector<float>(kLanes, 0.0f)};
        const auto compiled = check_same<float>(tape, kLanes, nullptr, &arguments);
        // Values held in registers across an exp (read after it, made before it: X·Y and the
        // output X − Y), through chunks that take the call.
        ir::Graph held_graph;
        const ir::NodeId hx = held_graph.argument(0), hy = held_graph.argument(1), hz = held_graph.argument(2);
        const ir::NodeId product = held_graph.make(Op::Mul, std::array{hx, hy});
        const ir::NodeId difference = held_graph.make(Op::Sub, std::array{hx, hy});
        const ir::NodeId exp_z = held_graph.make(Op::Exp, std::array{held_graph.make(Op::Mul, std::array{hz, hy})});
        const ir::NodeId sum = held_graph.make(Op::Add, std::array{held_graph.make(Op::Add, std::array{product, difference}),
                                                                    held_graph.make(Op::Mul, std::array{exp_z, product})});
        const Tape held_tape = compile_tape(held_graph, TapeSpec{{sum, difference}, {}, {}});
        std::vector<float> zs(kLanes), ones(kLanes, 1.0f);
        for (int l = 0; l < kLanes; ++l) zs[l] = xs[l];
        const Arguments<float> held_arguments{ys, ones, zs};
        check_same<float>(held_tape, kLanes, nullptr, &held_arguments);
        // The wide lanes gave what exp and ln give there.
        CHECK(compiled[0][16 * 32 + (16 * 5) % 32] == inf);   // exp(89.5) overflows
        CHECK(std::isnan(compiled[1][18 * 32 + (18 * 5) % 32]));   // ln(NaN)
        CHECK(compiled[1][20 * 32 + (20 * 5) % 32] == -inf);   // ln(-0)
    });
}

TEST_CASE("compiled division by a constant: by the reciprocal where exact, chunks with a lane out of range divided") {
    if (!tape_jit_available()) return;
    at_each_width([&] {
        // Powers of two (the reciprocal), divisors within Markstein's bound (the corrected
        // reciprocal), others (divided), of both signs; one output each, of X read from memory
        // and of X · Y (Y = 1) held in registers.
        const double divisors[] = {1, 0.5, -16, 0.9, 1.5, 11, -0.7, 0.15, 30.555555, 1.99999988};
        ir::Graph g;
        const ir::NodeId x = g.argument(0), held = g.make(Op::Mul, std::array{x, g.argument(1)});
        std::vector<ir::NodeId> quotients;
        for (ir::NodeId numerator : {x, held})
            for (double c : divisors) quotients.push_back(g.make(Op::Div, std::array{numerator, g.constant(c)}));
        const Tape tape = compile_tape(g, TapeSpec{quotients, {}, {}});
        constexpr int kLanes = 1024;
        const auto check = [&]<class T>(T, std::size_t by_reciprocal) {
            std::unique_ptr<CompiledTape<T>> jit = CompiledTape<T>::compile(tape);
            REQUIRE(jit);
            CHECK(jit->divisions_by_reciprocal() == by_reciprocal);
            // The first half ordinary numerators of every magnitude in the range; in the second
            // half each chunk has one lane of another kind, at a different place.
            constexpr int kRange = CorrectedRange<T>::kExponent;
            std::mt19937 random(5);
            std::uniform_real_distribution<double> significand(-2, 2);
            std::uniform_int_distribution<int> exponent(-kRange, kRange - 1);
            std::vector<T> xs(kLanes);
            for (T& v : xs) v = std::ldexp(T(significand(random)), exponent(random));
            const T inf = std::numeric_limits<T>::infinity(), low = std::ldexp(T(1), -kRange), high = std::ldexp(T(1), kRange);
            const T edges[] = {T(0), T(-0.0), inf, -inf, std::numeric_limits<T>::quiet_NaN(), std::numeric_limits<T>::denorm_min(),
                               std::nextafter(low, T(0)), -low, high, -std::nextafter(high, inf), std::numeric_limits<T>::max(),
                               std::numeric_limits<T>::min()};
            constexpr int kEdges = sizeof(edges) / sizeof(edges[0]);
            const int kChunk = jit->chunk_lanes();
            for (int chunk = kLanes / kChunk / 2, k = 0; chunk < kLanes / kChunk; ++chunk, ++k)
                xs[chunk * kChunk + (chunk * 7) % kChunk] = edges[k % kEdges];
            const Arguments<T> arguments{xs, std::vector<T>(kLanes, T(1)), std::vector<T>(kLanes, T(0))};
            const auto compiled = check_same<T>(tape, kLanes, nullptr, &arguments);
            // And as the division gives them, not only as the lane kernel does.
            for (std::size_t k = 0; k < compiled.size(); ++k)
                for (int l = 0; l < kLanes; ++l)
                    if (!std::isnan(xs[l])) REQUIRE(same_value(compiled[k][l], T(xs[l] / T(divisors[k % std::size(divisors)]))));
            // Code with other divisors than those compiled (a power of two for each): where one is
            // not of the kind compiled for, the lane kernel runs; the values are right either way.
            std::vector<Instruction> other = tape.code;
            for (Instruction& ins : other)
                if (ins.op == Op::Div) ins.constant[1] = 4.0;
            check_same<T>(tape, kLanes, &other, &arguments);
        };
        // float32: 1, 0.5 and -16 exact; 0.9, 1.5, 11, -0.7 and 0.15 corrected; 30.555555 and
        // 2 − 2^-23 divided. float64: 0.9 is out of the bound too.
        check(0.0f, 2 * 8);
        check(0.0, 2 * 7);
    });
}

TEST_CASE("a sin and cos of one angle run as one sincos: in the lane loops, compiled, and the same bits") {
    at_each_width([&] {
        // A rotation by an angle that varies over the domain, as RANOK's twisted blades write it.
        auto c = test::compile_text("ARGUMENT X, Y, Z;\nA = 3 * Z + X * Y;\nXX = X * COS(A) + Z * SIN(A);\n"
                                    "YY = -X * SIN(A) + Z * COS(A);\nRETURN 0.5 - XX * XX - 4 * YY * YY - Y * Y;\n");
        REQUIRE_MESSAGE(c.model, c.sink.render_all());
        // The lane loops: the pair's lanes are run_float_sincos's, which differ from SLEEF's own
        // sin and cos in the last bit here and there (so the pair did not run them).
        const Tape tape = compile_tape(c.model->graph, c.model->root);
        std::size_t pair = tape.code.size();
        for (std::size_t i = 0; i + 1 < tape.code.size(); ++i)
            if (sincos_twins(tape.code[i], tape.code[i + 1])) pair = i;
        REQUIRE(pair < tape.code.size());
        constexpr int kLanes = 4096;
        std::vector<std::vector<float>> storage(tape.slot_count, std::vector<float>(kLanes, 0.0f));
        std::vector<float*> slots(tape.slot_count);
        for (uint32_t s = 0; s < tape.slot_count; ++s) slots[s] = storage[s].data();
        for (auto [slot, axis] : tape.arguments)
            for (int l = 0; l < kLanes; ++l) storage[slot][l] = float(std::ldexp(l - kLanes / 2, -9) * (axis + 1));
        // Up to the pair only: later instructions may reuse the angle's or the pair's slots.
        run_lanes<float, 0>(tape.code.data(), pair + 2, slots.data(), kLanes);
        const Instruction& first = tape.code[pair];
        const Instruction& second = tape.code[pair + 1];
        const float* angle = slots[first.in[0]];
        std::vector<float> sines(kLanes), cosines(kLanes), sines_alone(kLanes);
        REQUIRE(vector_math::run_float_sincos(angle, sines.data(), cosines.data(), kLanes));
        REQUIRE(vector_math::run_float(Op::Sin, angle, nullptr, 0, 0, 0, sines_alone.data(), kLanes));
        const float* got_sin = slots[first.op == Op::Sin ? first.out : second.out];
        const float* got_cos = slots[first.op == Op::Sin ? second.out : first.out];
        int sin_differs = 0, cos_differs = 0, alone_differs = 0;
        for (int l = 0; l < kLanes; ++l) {
            sin_differs += std::memcmp(&got_sin[l], &sines[l], 4) != 0;
            cos_differs += std::memcmp(&got_cos[l], &cosines[l], 4) != 0;
            alone_differs += std::memcmp(&sines_alone[l], &sines[l], 4) != 0;
        }
        CHECK(sin_differs == 0);
        CHECK(cos_differs == 0);
        CHECK(alone_differs > 0);
        // Compiled: one site for the pair, the lane loops' bits.
        if (!tape_jit_available()) return;
        Grid cube;
        cube.dims = 3;
        cube.x = cube.y = cube.z = {-1.1, 1.2, 41};
        const auto [compiled, lanes] = compiled_and_lanes(*c.model, cube, Precision::Float32);
        REQUIRE(compiled.values.size() == lanes.values.size());
        CHECK(same_values(compiled.values, lanes.values));
    });
}
