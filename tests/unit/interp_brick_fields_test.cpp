// tests/unit/interp_brick_fields_test.cpp — a brick's components (the M-images of a bricked
// run) equal the FV model of the in-memory voxel field bit for bit, with ragged bricks, on
// the FLOZ3 sphere, bear.vm and a RANOK 3D script.
#include "interp_test_support.hpp"

#include "interp/brick_fields.hpp"
#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <cstring>
#include <filesystem>

using namespace fortu;

namespace {

/// Nodes (times components) where bricks of `layout` disagree with the whole field's
/// values or FV model in their bits.
std::size_t mismatches(const Model& model, const BrickLayout& layout) {
    const Grid& grid = layout.grid;
    const Field full = evaluate_grid(model, grid, engine_named("voxel"));
    const FvModel fv(full);
    BrickFieldEvaluator evaluator(model.graph, model.root, grid, true);
    BrickFields fields;
    std::size_t bad = 0;
    auto differ = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) != 0; };
    for (std::size_t b = 0; b < layout.size(); ++b) {
        const BrickBox box = layout.box(b);
        evaluator.evaluate(box, fields);
        REQUIRE(fields.components.size() == 5 * box.points());
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r)
                for (int c = box.lo[0]; c <= box.hi[0]; ++c) {
                    const std::size_t at = box.local(c, r, s), node = grid.index(c, r, s);
                    bad += differ(fields.values[at], full.values[node]);
                    for (int k = 1; k <= 5; ++k) bad += differ(fields.components[(k - 1) * box.points() + at], fv.n(k, node));
                }
    }
    return bad;
}

}  // namespace

TEST_CASE("bricks with their overlap give the in-memory field's components bit for bit") {
    const std::filesystem::path shared(FORTU_SHARED_DIR);
    for (const std::filesystem::path& path :
         {std::filesystem::path(FORTU_SOURCE_DIR) / "examples" / "floz3_sphere80.fortu", shared / "data" / "bear.vm",
          shared / "data" / "ranok-scripts" / "Tor.fortu"}) {
        CAPTURE(path.string());
        const std::optional<Model> model = test::load_model_file(path);
        REQUIRE(model);
        const Grid grid = model_grid(*model, {29, 23, 19});
        CHECK(mismatches(*model, BrickLayout(grid, 8)) == 0);                  // cubes, ragged last ones
        CHECK(mismatches(*model, BrickLayout::whole_rows(grid, 16)) == 0);     // whole rows, as .vti bricks
        CHECK(mismatches(*model, BrickLayout(grid, std::array<int, 3>{29, 1, 1})) == 0);   // one row thick
    }
}

TEST_CASE("without components a brick is its values alone, and the byte estimate counts the overlap") {
    test::Compiled c = test::compile_text("ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nRETURN 0.8 - X^2 - Y^2 - Z^2;\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Grid grid = model_grid(*c.model, {37, 37, 37});
    BrickFieldEvaluator evaluator(c.model->graph, c.model->root, grid, false);
    BrickFields fields;
    const BrickLayout layout(grid, 16);
    const BrickStats stats = evaluator.evaluate(layout.box(0), fields);
    CHECK(fields.values.size() == 16 * 16 * 16);
    CHECK(fields.components.empty());
    CHECK(stats.evaluated_points == 16 * 16 * 16);
    CHECK(brick_fields_bytes(layout, false) == 8 * 16 * 16 * 16);
    // The reach (17³) and the own values with n1..n5 (6 × 16³).
    CHECK(brick_fields_bytes(layout, true) == 8 * (17 * 17 * 17 + 6 * 16 * 16 * 16));
}
