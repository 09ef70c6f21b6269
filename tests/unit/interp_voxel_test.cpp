// tests/unit/interp_voxel_test.cpp — the voxel engine's modes: float64 equals the classic
// engine; float32 stays within the documented tolerance; thread counts and partial tiles
// give identical values.
#include "interp_test_support.hpp"

#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

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

Grid square_grid(int dims, int nodes) {
    Grid g;
    g.dims = dims;
    g.x.nodes = g.y.nodes = nodes;
    g.z.nodes = dims == 3 ? nodes : 1;
    return g;
}

}  // namespace

TEST_CASE("float64 voxel values equal the classic engine's on the .vm models") {
    for (const char* name : {"hi.vm", "quarter.vm", "tanglecube.vm", "colonnade.vm"}) {
        CAPTURE(name);
        const Model model = load_vm(name);
        const Grid grid = square_grid(model.dims(), model.dims() == 3 ? 12 : 37);
        const Field voxel = evaluate_grid(model, grid, EngineKind::Voxel);
        const Field classic = evaluate_grid(model, grid, EngineKind::Classic);
        for (std::size_t i = 0; i < voxel.values.size(); ++i) CHECK(voxel.values[i] == classic.values[i]);
    }
}

TEST_CASE("thread counts and partial tiles do not change values") {
    const Model model = load_vm("prospero.vm");
    const Grid grid = square_grid(2, 123);  // 15129 points: not a multiple of the tile
    EvalOptions one;
    one.threads = 1;
    EvalOptions two;
    two.threads = 2;
    const Field a = evaluate_grid(model, grid, EngineKind::Voxel, one);
    const Field b = evaluate_grid(model, grid, EngineKind::Voxel, two);
    CHECK(a.values == b.values);
    for (double v : a.values) CHECK(std::isfinite(v));
}

TEST_CASE("float32 stays within 1e-5 of the field's scale on the .vm models") {
    // Not bear.vm: its exp/ln blends leave float32's range at the box corners (below).
    for (std::string name : {"prospero.vm", "hi.vm", "quarter.vm", "colonnade.vm", "tanglecube.vm"}) {
        CAPTURE(name);
        const Model model = load_vm(name.c_str());
        const Grid grid = square_grid(model.dims(), model.dims() == 3 ? 20 : 101);
        EvalOptions f32;
        f32.precision = Precision::Float32;
        const Field exact = evaluate_grid(model, grid, EngineKind::Voxel);
        const Field fast = evaluate_grid(model, grid, EngineKind::Voxel, f32);
        double scale = 0;
        for (double v : exact.values) scale = std::max(scale, std::fabs(v));
        double worst = 0;
        for (std::size_t i = 0; i < exact.values.size(); ++i)
            worst = std::max(worst, std::fabs(exact.values[i] - fast.values[i]));
        CAPTURE(worst / scale);
        CHECK(worst <= 1e-5 * scale);
        CHECK(fast.values != exact.values);  // it really ran in single precision
    }
}

TEST_CASE("float32 beyond its range: bear.vm differs only at 6 corner points of 20³") {
    const Model model = load_vm("bear.vm");
    const Grid grid = square_grid(3, 20);
    EvalOptions f32;
    f32.precision = Precision::Float32;
    const Field exact = evaluate_grid(model, grid, EngineKind::Voxel);
    const Field fast = evaluate_grid(model, grid, EngineKind::Voxel, f32);
    int beyond = 0;
    for (std::size_t i = 0; i < exact.values.size(); ++i)
        beyond += std::fabs(exact.values[i] - fast.values[i]) > 1e-5 * 3.1425574031298424;
    CHECK(beyond == 6);
}
