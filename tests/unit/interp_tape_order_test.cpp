// tests/unit/interp_tape_order_test.cpp — the order of a tape with reused slots
// (tape.cpp, locality_order): depth-first, so a model imported level by level keeps few
// values alive at once, with the same values as its id order.
#include "interp_test_support.hpp"

#include "interp/box_simplify.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/tape.hpp"
#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

using namespace fortu;

namespace {

Model load_vm(const char* name) {
    std::string error;
    auto source = SourceFile::load((std::filesystem::path(FORTU_SHARED_DIR) / "data" / name).string(), error);
    if (!source) throw std::runtime_error(error);
    DiagnosticSink sink;
    std::optional<Model> model = import_vm(source, sink);
    if (!model) throw std::runtime_error(sink.render_all());
    return std::move(*model);
}

/// The root's values at `points` by the lane kernel, every slot a lane array.
std::vector<double> run_tape(const Tape& tape, const std::vector<std::array<double, 3>>& points) {
    const int n = static_cast<int>(points.size());
    std::vector<double> lanes(std::size_t(tape.slot_count) * n, 0.0);
    std::vector<double*> slots(tape.slot_count);
    for (std::size_t k = 0; k < slots.size(); ++k) slots[k] = lanes.data() + k * n;
    for (auto [slot, axis] : tape.arguments)
        for (int l = 0; l < n; ++l) slots[slot][l] = points[l][axis];
    for (auto [slot, value] : tape.constants) std::fill_n(slots[slot], n, value);
    run_lanes<double, 0>(tape.code.data(), tape.code.size(), slots.data(), n);
    return std::vector<double>(slots[tape.root_slot], slots[tape.root_slot] + n);
}

}  // namespace

TEST_CASE("reused slots follow a depth-first order: bear.vm, imported level by level, needs 24 slots, not 69") {
    const Model bear = load_vm("bear.vm");
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
    const std::vector<double> expected = run_tape(ssa, points);
    const std::vector<double> actual = run_tape(ordered, points);
    int differing = 0;
    for (std::size_t l = 0; l < points.size(); ++l) differing += std::memcmp(&actual[l], &expected[l], sizeof(double)) != 0;
    CHECK(differing == 0);
}
