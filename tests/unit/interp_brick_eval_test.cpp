// tests/unit/interp_brick_eval_test.cpp — bricks evaluated alone (interval-pruned tapes on the
// full grid's coordinates) equal the in-memory voxel engine bit for bit, on every 3D model we
// ship: the examples, the .vm models and the RANOK scripts; and a sparse writer's skipped
// sub-boxes lie outside its band.
#include "interp_test_support.hpp"

#include "interp/brick_eval.hpp"
#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>

using namespace fortu;

namespace {

/// Points where the bricked values differ from the voxel engine's in their bits; also
/// counts through `skipped` the points a band of `band` skipped, and checks they are beyond it.
std::size_t brick_mismatches(const Model& model, const Grid& grid, int edge, std::optional<double> band = std::nullopt,
                             std::size_t* skipped = nullptr) {
    const Field full = evaluate_grid(model, grid, engine_named("voxel"));
    const BrickLayout layout(grid, edge);
    BrickEvaluator evaluator(model.graph, model.root, grid);
    std::vector<double> values;
    std::size_t bad = 0;
    for (std::size_t b = 0; b < layout.size(); ++b) {
        const BrickBox box = layout.box(b);
        const BrickStats st = evaluator.evaluate(box, values, band);
        if (skipped) *skipped += st.skipped_points;
        CHECK(st.evaluated_points + st.skipped_points == box.points());
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r)
                for (int c = box.lo[0]; c <= box.hi[0]; ++c) {
                    const double expected = full.values[grid.index(c, r, s)], got = values[box.local(c, r, s)];
                    if (band && std::isinf(got) && !std::isinf(expected)) {
                        bad += !(std::fabs(expected) > *band && std::signbit(expected) == std::signbit(got));
                        continue;
                    }
                    bad += std::bit_cast<std::uint64_t>(expected) != std::bit_cast<std::uint64_t>(got) &&
                           !(std::isnan(expected) && std::isnan(got));
                }
    }
    return bad;
}

std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir, const std::string& ext) {
    std::vector<std::filesystem::path> files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ext) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

TEST_CASE("bricks cover the grid once, the last ones cut to it") {
    Grid g;
    g.dims = 3;
    g.x.nodes = 37;
    g.y.nodes = 16;
    g.z.nodes = 17;
    const BrickLayout layout(g, 16);
    CHECK(layout.counts == std::array<int, 3>{3, 1, 2});
    std::vector<int> covered(g.points(), 0);
    for (std::size_t b = 0; b < layout.size(); ++b) {
        const BrickBox box = layout.box(b);
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r)
                for (int c = box.lo[0]; c <= box.hi[0]; ++c) ++covered[g.index(c, r, s)];
    }
    CHECK(std::count(covered.begin(), covered.end(), 1) == std::ptrdiff_t(g.points()));
    CHECK(layout.box(5).lo == std::array<int, 3>{32, 0, 16});
    CHECK(layout.box(5).hi == std::array<int, 3>{36, 15, 16});
}

TEST_CASE("bricked values equal the voxel engine bit for bit on every 3D model we ship") {
    std::vector<std::filesystem::path> files = files_in(std::filesystem::path(FORTU_SOURCE_DIR) / "examples", ".fortu");
    for (const auto& f : files_in(std::filesystem::path(FORTU_SHARED_DIR) / "data", ".vm")) files.push_back(f);
    for (const auto& f : files_in(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "ranok-scripts", ".fortu"))
        files.push_back(f);
    int checked = 0;
    for (const auto& path : files) {
        CAPTURE(path.string());
        std::optional<Model> model = test::load_model_file(path);
        if (!model || model->dims() != 3) continue;
        const Grid grid = model_grid(*model, {29, 23, 19});   // bricks of 8 and 16: ragged last ones
        CHECK(brick_mismatches(*model, grid, 8) == 0);
        CHECK(brick_mismatches(*model, grid, 16) == 0);
        ++checked;
    }
    CHECK(checked >= 20);
}

TEST_CASE("a sparse band skips sub-boxes outside it, and keeps every value inside it exact") {
    // A ball: tight intervals (the FLOZ3 sphere's R0 formulas are too loose to skip anything).
    test::Compiled c = test::compile_text("ARGUMENT X(-1, 1), Y(-1, 1), Z(-1, 1);\nRETURN 0.8 - SQRT(X^2 + Y^2 + Z^2);\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Grid grid = model_grid(*c.model, {65, 65, 65});
    std::size_t skipped = 0;
    CHECK(brick_mismatches(*c.model, grid, 32, 3 * grid.x.step(), &skipped) == 0);
    CHECK(skipped > grid.points() * 4 / 10);   // the band is a thin shell (49% skipped with 8³ leaves)
}
