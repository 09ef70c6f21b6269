// tests/unit/interp_ranok_scripts_test.cpp — every real RANOK script (shared/data/
// ranok-scripts, enumerated, so a new file is tested automatically) compiles, runs with the
// voxel engine, and the classic engine agrees with it: at a handful of points always, and
// on the whole small grid whenever the classic estimate fits the test's budget.
#include "interp_test_support.hpp"

#include "interp/classic_cost.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

using namespace fortu;

namespace {

bool agree(double a, double b) {
    if (!std::isfinite(a) || !std::isfinite(b)) return std::isnan(a) == std::isnan(b) && (std::isnan(a) || a == b);
    return std::fabs(a - b) <= 1e-9 * std::max({1e-300, std::fabs(a), std::fabs(b)}) || a == b;
}

Grid small_grid(const Model& model) {
    return model_grid(model, model.dims() == 3 ? std::array<int, 3>{24, 24, 24} : std::array<int, 3>{48, 48, 1});
}

std::vector<std::filesystem::path> ranok_scripts() {
    std::vector<std::filesystem::path> files;
    const std::filesystem::path dir = std::filesystem::path(FORTU_SHARED_DIR) / "data" / "ranok-scripts";
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().extension() == ".fortu") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

TEST_CASE("all ranok-scripts compile, run with voxel, and classic agrees") {
    const auto files = ranok_scripts();
    REQUIRE(files.size() >= 56);
    int whole_grid_compared = 0;
    for (const auto& path : files) {
        CAPTURE(path.filename().string());
        std::string error;
        auto source = SourceFile::load(path.string(), error);
        REQUIRE(source);
        DiagnosticSink sink;
        std::optional<Model> model = compile(source, {}, sink);
        REQUIRE_MESSAGE(model, sink.render_all());
        CHECK(sink.error_count() == 0);

        const Grid grid = small_grid(*model);
        const Field voxel = evaluate_grid(*model, grid, engine_named("voxel"));
        CHECK(voxel.values.size() == grid.points());
        CHECK(voxel.invalid_count() < grid.points());  // some finite values in the default box

        const double per_point = classic_operations_per_point(model->graph, model->root);
        const int samples = per_point > 1e8 ? 2 : 6;
        for (int s = 0; s < samples; ++s) {
            const double t = (s + 0.5) / samples;
            const int col = static_cast<int>(t * (grid.cols() - 1));
            const int row = static_cast<int>((1 - t) * (grid.rows() - 1));
            const int slice = static_cast<int>(t * (grid.slices() - 1));
            const std::array<double, 3> p{grid.x_at(col), grid.y_at(row), grid.z_at(slice)};
            const double classic = evaluate_point(*model, p, engine_named("classic")).value;
            const double stored = voxel.values[grid.index(col, row, slice)];
            CHECK_MESSAGE(agree(classic, stored), "classic ", classic, " voxel ", stored);
            CHECK(agree(evaluate_point(*model, p, engine_named("voxel")).value, stored));
        }
        if (per_point * double(grid.points()) <= 3e8) {
            const Field classic = evaluate_grid(*model, grid, engine_named("classic"));
            std::size_t disagreements = 0;
            for (std::size_t i = 0; i < grid.points(); ++i) disagreements += !agree(classic.values[i], voxel.values[i]);
            CHECK(disagreements == 0);
            ++whole_grid_compared;
        }
    }
    MESSAGE("whole grids compared with classic: ", whole_grid_compared, " of ", files.size());
    CHECK(whole_grid_compared >= 40);
}

TEST_CASE("Bone.fortu expands to about 4e8 classic operations per point") {
    std::string error;
    auto source = SourceFile::load(std::string(FORTU_SHARED_DIR) + "/data/ranok-scripts/Bone.fortu", error);
    REQUIRE(source);
    DiagnosticSink sink;
    auto model = compile(source, {}, sink);
    REQUIRE(model);
    const double cost = classic_operations_per_point(model->graph, model->root);
    CHECK(cost > 1e8);
    CHECK(cost < 1e9);
}
