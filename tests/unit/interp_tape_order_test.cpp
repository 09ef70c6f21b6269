// tests/unit/interp_tape_order_test.cpp — the order of a tape with reused slots
// (tape.cpp, locality_order): depth-first, so a model imported level by level keeps few
// values alive at once, with the same values as its id order.
#include "interp_test_support.hpp"

#include "interp/box_simplify.hpp"
#include "interp/tape.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

using namespace fortu;

TEST_CASE("reused slots follow a depth-first order: bear.vm, imported level by level, needs 24 slots, not 69") {
    const std::optional<Model> loaded = test::load_model_file(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "bear.vm");
    REQUIRE(loaded);
    const Model& bear = *loaded;
    const Tape ssa = compile_tape(bear.graph, TapeSpec{{bear.root}, {}, {}, /*reuse_slots=*/false});
    const Tape ordered = compile_tape(bear.graph, TapeSpec{{bear.root}, {}, {}, /*reuse_slots=*/true});
    // The SSA tape keeps the ids' (the file's) order; its slots reused in that order:
    Tape in_id_order;
    SlotScratch scratch;
    reallocate_slots(ssa, in_id_order, scratch);
    CHECK(ssa.code.size() == 544);
    CHECK(ordered.code.size() == 544);
    CHECK(in_id_order.slot_count == 69);
    CHECK(ordered.slot_count == 24);
    // Every instruction's operands come before it, and the values are the same bits.
    std::vector<char> written(ordered.slot_count, 0);
    written[ordered.zero_slot] = 1;
    for (auto [slot, axis] : ordered.arguments) written[slot] = 1;
    bool operands_first = true;
    for (const Instruction& ins : ordered.code) {
        for (int k = 0; k < ir::op_arity(ins.op); ++k)
            if (!(ins.constant_operands >> k & 1u)) operands_first = operands_first && written[ins.in[k]];
        written[ins.out] = 1;
    }
    CHECK(operands_first);
    std::vector<std::array<double, 3>> points;
    for (int i = 0; i < 64; ++i) points.push_back({-1.0 + i / 32.0, 0.75 - i / 50.0, (i % 7) / 3.5 - 1.0});
    const std::vector<double> expected = test::run_tape(ssa, points);
    const std::vector<double> actual = test::run_tape(ordered, points);
    int differing = 0;
    for (std::size_t l = 0; l < points.size(); ++l) differing += std::memcmp(&actual[l], &expected[l], sizeof(double)) != 0;
    CHECK(differing == 0);
}

TEST_CASE("a sin and a cos of one operand sit side by side in both tape kinds, wherever the model writes them") {
    // COS(T) early, SIN(T) at the end, SIN(U) without a twin, COS of a constant folded.
    auto c = test::compile_text("ARGUMENT X, Y;\nT = X * Y + 0.5;\nU = X - Y;\nA = X * COS(T) + SIN(U);\n"
                                "B = A * A - Y * COS(2) + Y;\nRETURN B + X * SIN(T);\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    for (const bool reuse : {false, true}) {
        CAPTURE(reuse);
        const Tape tape = compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, reuse});
        int twins = 0, sines = 0, cosines = 0;
        for (std::size_t i = 0; i < tape.code.size(); ++i) {
            sines += tape.code[i].op == ir::Op::Sin;
            cosines += tape.code[i].op == ir::Op::Cos;
            if (i + 1 < tape.code.size()) twins += sincos_twins(tape.code[i], tape.code[i + 1]);
        }
        CHECK(sines == 2);
        CHECK(cosines == 1);
        CHECK(twins == 1);
    }
}
