// Which operands the tape compiler may treat as never NaN: in float64 by the interval
// contract over the grid, in float32 by the structural rule with a magnitude bound; whatever
// can be NaN (a square root of a negative value, a division by zero, float32's overflow, values
// kept from elsewhere) is never claimed a number.
#include "interp/number_operands.hpp"
#include "interp/tape.hpp"

#include <doctest/doctest.h>

#include <array>

using namespace fortu;
using ir::Op;

namespace {

Grid plane(double x_min, double x_max, double y_min = -1, double y_max = 1) {
    Grid g;
    g.dims = 2;
    g.x = {x_min, x_max, 64};
    g.y = {y_min, y_max, 64};
    return g;
}

/// The number bits of the instruction computing `root` (the tape's last), as bit 0 for the
/// operand `first` and bit 1 for `second` (the graph orders a commutative operation's operands
/// by id, the tape as the graph).
unsigned root_bits(const ir::Graph& graph, ir::NodeId root, ir::NodeId first, ir::NodeId second, const Grid& grid,
                   Precision precision, const TapeSpec* with = nullptr, std::size_t opaque_inputs = 0) {
    const TapeSpec spec = with ? *with : TapeSpec{{root}, {}, {}};
    const Tape tape = compile_tape(graph, spec);
    const std::vector<uint8_t> bits = number_operands(graph, spec, tape, grid, precision, opaque_inputs);
    REQUIRE(bits.size() == tape.code.size());
    const ir::Node& n = graph.node(root);
    REQUIRE(((n.args[0] == first && n.args[1] == second) || (n.args[0] == second && n.args[1] == first)));
    const bool swapped = n.args[0] == second;
    const unsigned b = bits.back();
    return swapped ? ((b & 1u) << 1) | ((b >> 1) & 1u) : b;
}

}  // namespace

TEST_CASE("number operands: a square root of a value that may be negative may be NaN") {
    ir::Graph g;
    const auto x = g.argument(0), y = g.argument(1);
    const auto root_x = g.unary(Op::Sqrt, x);
    const auto root = g.binary(Op::Max, root_x, y);   // max(sqrt(x), y)
    for (Precision p : {Precision::Float64, Precision::Float32}) {
        CAPTURE(int(p));
        CHECK(root_bits(g, root, root_x, y, plane(-1, 1), p) == 0b10);   // x < 0 on the grid: only y
        CHECK(root_bits(g, root, root_x, y, plane(0, 1), p) == 0b11);    // x ≥ 0 everywhere
    }
}

TEST_CASE("number operands: sums of squares under a root are numbers in both precisions") {
    ir::Graph g;
    const auto x = g.argument(0), y = g.argument(1);
    const auto radius = g.unary(Op::Sqrt, g.binary(Op::Add, g.unary(Op::Square, x), g.binary(Op::Mul, y, y)));
    const auto difference = g.unary(Op::Sqrt, g.binary(Op::Sub, x, y));
    const auto root = g.binary(Op::Min, radius, difference);
    for (Precision p : {Precision::Float64, Precision::Float32}) {
        CAPTURE(int(p));
        CHECK(root_bits(g, root, radius, difference, plane(-1, 1), p) == 0b01);
    }
    // y·y is ≥ 0 by the float32 rule only as a square or a product of values ≥ 0: x·y is not.
    const auto product_root = g.unary(Op::Sqrt, g.binary(Op::Mul, x, y));
    const auto mixed = g.binary(Op::Min, product_root, y);
    CHECK(root_bits(g, mixed, product_root, y, plane(0.5, 1, 0.5, 1), Precision::Float32) == 0b11);
    CHECK(root_bits(g, mixed, product_root, y, plane(-1, 1), Precision::Float32) == 0b10);
    CHECK(root_bits(g, mixed, product_root, y, plane(-1, 1), Precision::Float64) == 0b10);
}

TEST_CASE("number operands: float64 follows the intervals, float32 only its structural rule") {
    ir::Graph g;
    const auto x = g.argument(0), y = g.argument(1);
    // x / (y² + 1): never a division by zero, which the intervals know.
    const auto quotient = g.binary(Op::Div, x, g.binary(Op::Add, g.unary(Op::Square, y), g.constant(1)));
    const auto root = g.binary(Op::Max, quotient, y);
    CHECK(root_bits(g, root, quotient, y, plane(-1, 1), Precision::Float64) == 0b11);
    CHECK(root_bits(g, root, quotient, y, plane(-1, 1), Precision::Float32) == 0b10);
    // x / y: y = 0 is on the grid's box.
    const auto ratio = g.binary(Op::Div, x, y);
    const auto risky = g.binary(Op::Max, ratio, x);
    CHECK(root_bits(g, risky, ratio, x, plane(-1, 1), Precision::Float64) == 0b10);
}

TEST_CASE("number operands: float32 overflow to infinity is not a number's guarantee") {
    ir::Graph g;
    const auto x = g.argument(0), y = g.argument(1);
    const auto big = g.binary(Op::Mul, g.binary(Op::Mul, x, g.constant(1e30)), g.constant(1e30));   // up to 1e60
    const auto zero = g.binary(Op::Sub, big, big);   // ∞ − ∞ in float32
    const auto root = g.binary(Op::Min, zero, y);
    CHECK(root_bits(g, root, zero, y, plane(-1, 1), Precision::Float64) == 0b11);
    CHECK(root_bits(g, root, zero, y, plane(-1, 1), Precision::Float32) == 0b10);
    const auto fits = g.binary(Op::Mul, x, g.constant(1e30));
    const auto small_zero = g.binary(Op::Sub, fits, fits);
    const auto fine = g.binary(Op::Min, small_zero, y);
    CHECK(root_bits(g, fine, small_zero, y, plane(-1, 1), Precision::Float32) == 0b11);
}

TEST_CASE("number operands: values kept from elsewhere are not known; hoisted inputs are their nodes'") {
    ir::Graph g;
    const auto x = g.argument(0), y = g.argument(1);
    const auto column = g.unary(Op::Square, x);                     // an input: X-only
    const auto root = g.binary(Op::Max, column, y);
    const TapeSpec spec{{root}, {column}, {}};
    for (Precision p : {Precision::Float64, Precision::Float32}) {
        CAPTURE(int(p));
        CHECK(root_bits(g, root, column, y, plane(-1, 1), p, &spec, 0) == 0b11);
        CHECK(root_bits(g, root, column, y, plane(-1, 1), p, &spec, 1) == 0b10);
    }
    // A uniform (one value per row) patched in as a constant operand: the node's facts.
    const auto row = g.unary(Op::Sqrt, y);
    const auto with_row = g.binary(Op::Min, row, x);
    const TapeSpec uniform_spec{{with_row}, {}, {row}};
    CHECK(root_bits(g, with_row, row, x, plane(-1, 1), Precision::Float64, &uniform_spec) == 0b10);
    CHECK(root_bits(g, with_row, row, x, plane(-1, 1, 0, 1), Precision::Float64, &uniform_spec) == 0b11);
}
