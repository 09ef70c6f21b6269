// tests/unit/interp_compiled_tape_cache_test.cpp — compiled tapes found again by content:
// compiled on the second sighting, never handed out for a tape that differs in anything the
// code depends on, within the instruction budget; and a shaded view whose leaves run them is
// the lane loops' picture bit for bit.
#include "interp_test_support.hpp"

#include "interp/compiled_tape_cache.hpp"
#include "interp/shaded_view.hpp"

#include <doctest/doctest.h>

#include <cstring>

using namespace fortu;

namespace {

Tape ssa_tape_of(const std::string& text) {
    test::Compiled c = test::compile_text(text);
    REQUIRE(c.model);
    return compile_tape(c.model->graph, TapeSpec{{c.model->root}, {}, {}, false});
}

}  // namespace

TEST_CASE("a compiled tape is made on the second sighting of its content and found again") {
    if (!tape_jit_available()) return;   // nothing is compiled on this CPU
    const Tape tape = ssa_tape_of("ARGUMENT X, Y\nRETURN EXP(X) * SQRT(1 + Y*Y) - 2.5");
    CompiledTapeCache<float> cache;
    CHECK(cache.find(tape) == nullptr);
    const CompiledTape<float>* code = cache.find(tape);
    REQUIRE(code != nullptr);
    const Tape copy = tape;   // another object, the same content
    CHECK(cache.find(copy) == code);
    CHECK(cache.compiled() == 1);
    CHECK(cache.hits() == 2);

    // Anything the code depends on makes another tape: a constant operand's bits, an
    // operation, an argument's axis.
    Tape other_constant = tape;
    for (Instruction& ins : other_constant.code)
        if (ins.constant_operands) {
            ins.constant[std::countr_zero(unsigned(ins.constant_operands))] = 2.5000000000000004;
            break;
        }
    Tape other_axis = tape;
    other_axis.arguments[0].second = 2;
    Tape other_op = tape;
    for (Instruction& ins : other_op.code)
        if (ins.op == ir::Op::Exp) ins.op = ir::Op::Ln;
    for (const Tape* t : {&other_constant, &other_axis, &other_op}) {
        CHECK_FALSE(same_tape_content(*t, tape));
        CHECK(cache.find(*t) == nullptr);
        const CompiledTape<float>* again = cache.find(*t);
        CHECK(again != nullptr);
        CHECK(again != code);
    }
    CHECK(cache.find(tape) == code);
    CHECK(cache.compiled() == 4);
}

TEST_CASE("a compiled-tape cache keeps within its instruction budget") {
    if (!tape_jit_available()) return;
    const Tape small = ssa_tape_of("ARGUMENT X, Y\nRETURN X*X + Y");
    const Tape large = ssa_tape_of("ARGUMENT X, Y\nRETURN SIN(X)*COS(Y) + EXP(X*Y) - LN(1 + X*X) + SQRT(Y*Y + 1)");
    CompiledTapeCache<float> cache(large.code.size() + small.code.size() - 1);
    cache.find(large);
    CHECK(cache.find(large) != nullptr);
    // The small tape no longer fits: it runs in the lane loops however often it is seen.
    for (int i = 0; i < 3; ++i) CHECK(cache.find(small) == nullptr);
    CHECK(cache.find(large) != nullptr);
    CHECK(cache.compiled() == 1);
}

TEST_CASE("a shaded view with compiled leaf tapes is the lane loops' picture bit for bit") {
    // bear.vm: exp, ln, sin and cos (SLEEF and fortu's own in both paths) and leaves of every
    // tail length; the pawn: R-operations written out.
    for (const char* file : {"bear.vm", "pawn.fortu"}) {
        CAPTURE(file);
        const std::filesystem::path path = std::string(file) == "bear.vm"
                                               ? std::filesystem::path(FORTU_SHARED_DIR) / "data" / file
                                               : std::filesystem::path(FORTU_SOURCE_DIR) / "examples" / file;
        const std::optional<Model> model = test::load_model_file(path);
        REQUIRE(model);
        const Grid cube = model_grid(*model, {2, 2, 2});
        const std::array<AxisRange, 3> box{AxisRange{cube.x.min, cube.x.max}, AxisRange{cube.y.min, cube.y.max},
                                           AxisRange{cube.z.min, cube.z.max}};
        for (const ViewDirection view : {ViewDirection{0, 0}, ViewDirection{45, 35.26}}) {
            ShadedViewStats lane_stats, compiled_stats;
            const SurfaceImage lanes =
                render_shaded_view(model->graph, model->root, box, view, 192, 160, {}, false, &lane_stats);
            const SurfaceImage compiled =
                render_shaded_view(model->graph, model->root, box, view, 192, 160, {}, true, &compiled_stats);
            MESSAGE(std::string(file), ": ", compiled_stats.compiled_leaves, " of ", compiled_stats.leaves, " leaves compiled, ",
                    compiled_stats.tapes_compiled, " tapes");
            CHECK(lane_stats.compiled_leaves == 0);
            CHECK(compiled_stats.leaves == lane_stats.leaves);
            // Leaves share tapes with their neighbours (bear.vm from the front: 1,322 of 2,011 leaves
            // on 107 compiled tapes; iso: 562 of 1,372), where this CPU compiles at all.
            if (tape_jit_available()) CHECK(compiled_stats.compiled_leaves * 3 > compiled_stats.leaves);
            CHECK(compiled.hit == lanes.hit);
            REQUIRE(compiled.depth.size() == lanes.depth.size());
            CHECK(std::memcmp(compiled.depth.data(), lanes.depth.data(), lanes.depth.size() * sizeof(float)) == 0);
            CHECK(std::memcmp(compiled.normal.data(), lanes.normal.data(), lanes.normal.size() * sizeof(lanes.normal[0])) == 0);
            std::size_t hits = 0;
            for (SurfaceImage::Hit h : lanes.hit) hits += h == SurfaceImage::Hit::Surface;
            CHECK(hits > 2000);
        }
    }
}
