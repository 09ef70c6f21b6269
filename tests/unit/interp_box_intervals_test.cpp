// tests/unit/interp_box_intervals_test.cpp — the sign renderer's interval walk with choices
// (box_intervals.hpp) gives evaluate_intervals' ranges bit for bit, and the shortening from
// its choice bytes gives the tape the shortening from ranges gives, on every box of a
// quadtree/octree over real models.
#include "interp_test_support.hpp"

#include "interp/box_intervals.hpp"
#include "interp/box_simplify.hpp"
#include "interp/quadrant_intervals.hpp"

#include <doctest/doctest.h>

#include <bit>
#include <filesystem>
#include <string>
#include <vector>

using namespace fortu;

namespace {

bool same_bits(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }

bool same_tape(const Tape& a, const Tape& b) {
    if (a.code.size() != b.code.size() || a.root_slot != b.root_slot || a.slot_count != b.slot_count ||
        a.constants != b.constants || a.arguments != b.arguments)
        return false;
    for (std::size_t i = 0; i < a.code.size(); ++i) {
        const Instruction &x = a.code[i], &y = b.code[i];
        if (x.op != y.op || x.out != y.out || x.constant_operands != y.constant_operands || !same_bits(x.imm, y.imm))
            return false;
        for (int k = 0; k < ir::kMaxArity; ++k)
            if (x.in[k] != y.in[k] || !same_bits(x.constant[k], y.constant[k])) return false;
    }
    return true;
}

struct Walk {
    std::size_t boxes = 0;
    std::size_t range_mismatches = 0;   ///< slots whose ranges differ
    std::size_t tape_mismatches = 0;    ///< boxes whose shortened tapes differ
    std::size_t shortened = 0;          ///< boxes whose tape got shorter
    std::size_t quadrant_mismatches = 0;///< 2D quadrants whose choices or root range differ from their own walk's
};

/// The four quadrants of a 2D box.
std::array<std::array<Interval, 3>, 4> quadrants(const std::array<Interval, 3>& box) {
    std::array<std::array<Interval, 3>, 4> parts;
    for (int part = 0; part < 4; ++part) {
        parts[part] = box;
        for (int a = 0; a < 2; ++a) {
            const double mid = (box[a].lo + box[a].hi) / 2;
            parts[part][a] = (part >> a) & 1 ? Interval{mid, box[a].hi, false} : Interval{box[a].lo, mid, false};
        }
    }
    return parts;
}

/// Both passes on the box [lo, hi] and, to `depth` more levels, on its halves (each with the
/// tape its parent was shortened to, as the renderer walks).
void walk(const Tape& tape, std::array<Interval, 3> box, int dims, int depth, Walk& w) {
    std::vector<Interval> expected, got;
    std::vector<uint8_t> choices;
    evaluate_intervals(tape, box, expected);
    evaluate_box_intervals(tape, box, got, choices);
    ++w.boxes;
    for (const Instruction& ins : tape.code) {
        const Interval &e = expected[ins.out], &g = got[ins.out];
        if (!same_bits(e.lo, g.lo) || !same_bits(e.hi, g.hi) || e.maybe_nan != g.maybe_nan) ++w.range_mismatches;
    }
    BoxScratch scratch;
    Tape from_ranges, from_choices;
    simplify_for_sign(tape, expected, scratch, from_ranges);
    simplify_for_sign(tape, choices, scratch, from_choices);
    if (!same_tape(from_ranges, from_choices)) ++w.tape_mismatches;
    if (from_ranges.code.size() < tape.code.size()) ++w.shortened;
    if (depth == 0 || from_ranges.code.empty()) return;
    if (dims == 2) {
        const auto parts = quadrants(box);
        QuadrantScratch quadrant_scratch;
        std::array<std::vector<uint8_t>, 4> quadrant_choices;
        std::array<Interval, 4> roots;
        evaluate_quadrant_intervals(from_ranges, parts, quadrant_scratch, quadrant_choices, roots);
        for (int q = 0; q < 4; ++q) {
            evaluate_box_intervals(from_ranges, parts[q], got, choices);
            const Interval& root = got[from_ranges.root_slot];
            if (quadrant_choices[q] != choices || !same_bits(root.lo, roots[q].lo) || !same_bits(root.hi, roots[q].hi) ||
                root.maybe_nan != roots[q].maybe_nan)
                ++w.quadrant_mismatches;
        }
    }
    for (int part = 0; part < (1 << dims); ++part) {
        std::array<Interval, 3> child = box;
        for (int a = 0; a < dims; ++a) {
            const double mid = (box[a].lo + box[a].hi) / 2;
            child[a] = (part >> a) & 1 ? Interval{mid, box[a].hi, false} : Interval{box[a].lo, mid, false};
        }
        walk(from_ranges, child, dims, depth - 1, w);
    }
}

Walk walk_model(const Model& model, int depth) {
    const Grid grid = model_grid(model, {64, 64, model.dims() == 3 ? 64 : 1});
    const Tape tape = compile_tape(model.graph, TapeSpec{{model.root}, {}, {}, /*reuse_slots=*/false});
    std::array<Interval, 3> box{Interval{grid.x_at(0), grid.x_at(grid.cols() - 1), false},
                                Interval{grid.y_at(grid.rows() - 1), grid.y_at(0), false},
                                Interval{grid.z_at(0), grid.z_at(grid.slices() - 1), false}};
    for (Interval& r : box)
        if (r.lo > r.hi) std::swap(r.lo, r.hi);
    Walk w;
    walk(tape, box, model.dims(), depth, w);
    return w;
}

}  // namespace

TEST_CASE("box intervals: evaluate_intervals' ranges and the same shortened tapes on prospero.vm") {
    auto model = test::load_model_file(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "prospero.vm");
    REQUIRE(model);
    const Walk w = walk_model(*model, 6);
    CHECK(w.boxes == 4309);   // of the 5461 boxes of six levels, those not below a box whose tape became a constant
    CHECK(w.range_mismatches == 0);
    CHECK(w.tape_mismatches == 0);
    CHECK(w.quadrant_mismatches == 0);
    CHECK(w.shortened > w.boxes / 2);
}

TEST_CASE("box intervals: the same on every .vm model and RANOK script (NaN, poles, R-operations)") {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(FORTU_SHARED_DIR) / "data"))
        if (e.path().extension() == ".vm" && e.path().filename() != "prospero.vm") files.push_back(e.path());
    for (const auto& e :
         std::filesystem::directory_iterator(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "ranok-scripts"))
        if (e.path().extension() == ".fortu") files.push_back(e.path());
    REQUIRE(files.size() > 50);
    for (const auto& path : files) {
        CAPTURE(path.string());
        auto model = test::load_model_file(path);
        if (!model) continue;   // a script that does not compile is another test's business
        const Walk w = walk_model(*model, model->dims() == 3 ? 2 : 4);
        CHECK(w.range_mismatches == 0);
        CHECK(w.tape_mismatches == 0);
        CHECK(w.quadrant_mismatches == 0);
    }
}

TEST_CASE("box intervals: operands that may be NaN, poles and unbounded results take interval.cpp's rules") {
    auto c = test::compile_text("ARGUMENT X(-1, 1), Y(-1, 1)\n"
                                "RETURN MIN(SQRT(X) + 1 / Y, MAX(X * X * 1e200 * 1e200, -X)) & ABS(Y - 0.5) | TAN(X)\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Walk w = walk_model(*c.model, 5);
    CHECK(w.boxes == 1365);
    CHECK(w.range_mismatches == 0);
    CHECK(w.tape_mismatches == 0);
    CHECK(w.quadrant_mismatches == 0);
}
