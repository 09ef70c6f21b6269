// tests/unit/interp_voxel_test.cpp — the voxel engine's modes: float64 equals the classic
// engine; float32 stays within the documented tolerance; thread counts and partial tiles
// give identical values.
#include "interp_test_support.hpp"

#include "interp/hoist.hpp"
#include "interp/tape.hpp"
#include "interp/vm_import.hpp"
#include "interp/voxel_engine.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

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
        const Field voxel = evaluate_grid(model, grid, engine_named("voxel"));
        const Field classic = evaluate_grid(model, grid, engine_named("classic"));
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
    const Field a = evaluate_grid(model, grid, engine_named("voxel"), one);
    const Field b = evaluate_grid(model, grid, engine_named("voxel"), two);
    CHECK(a.values == b.values);
    for (double v : a.values) CHECK(std::isfinite(v));
}

TEST_CASE("float32 stays within 1e-5 of the field's scale on the .vm models") {
    // Not bear.vm: its exp/ln blends leave float32's range at the box corners (below).
    for (std::string name : {"prospero.vm", "hi.vm", "quarter.vm", "colonnade.vm", "tanglecube.vm"}) {
        CAPTURE(name);
        const Model model = load_vm(name.c_str());
        const Grid grid = square_grid(model.dims(), model.dims() == 3 ? 20 : 101);
        const Field exact = evaluate_grid(model, grid, engine_named("voxel"));
        const Field fast = evaluate_grid(model, grid, engine_named("voxel-f32"));
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
    const Field exact = evaluate_grid(model, grid, engine_named("voxel"));
    const Field fast = evaluate_grid(model, grid, engine_named("voxel-f32"));
    int beyond = 0;
    for (std::size_t i = 0; i < exact.values.size(); ++i)
        beyond += std::fabs(exact.values[i] - fast.values[i]) > 1e-5 * 3.1425574031298424;
    CHECK(beyond == 6);
}

TEST_CASE("hoisting X-only and row-only sub-expressions changes no value, in either precision") {
    // prospero.vm on 100 columns (tiles of 10 whole rows, the last of 7), 1030 (three
    // 352-lane pieces) and 40 (flat tiles, nothing hoisted); tanglecube.vm and bear.vm in 3D
    // (rows over two axes, XY and XZ planes; tiles of 9 rows (a whole slice), 9 + 4 and
    // 16 + 5 rows; one row per tile).
    struct Case { const char* name; int dims, cols, rows; };
    for (const Case c : {Case{"prospero.vm", 2, 100, 37}, Case{"prospero.vm", 2, 1030, 3}, Case{"prospero.vm", 2, 40, 40},
                         Case{"tanglecube.vm", 3, 70, 9}, Case{"tanglecube.vm", 3, 110, 13}, Case{"bear.vm", 3, 64, 21},
                         Case{"bear.vm", 3, 1030, 2}}) {
        CAPTURE(c.name);
        CAPTURE(c.cols);
        const Model model = load_vm(c.name);
        Grid grid = square_grid(c.dims, c.rows);
        grid.x.nodes = c.cols;
        for (Precision precision : {Precision::Float64, Precision::Float32}) {
            const VoxelEngine hoisted({.precision = precision}), plain({.precision = precision, .hoist = false});
            const Field a = evaluate_grid(model, grid, hoisted);
            const Field b = evaluate_grid(model, grid, plain);
            CHECK(a.values == b.values);
            if (precision == Precision::Float64)
                CHECK(a.values == evaluate_grid(model, grid, engine_named("classic")).values);
        }
    }
}

TEST_CASE("the hoisting plan: X-only nodes per column, nodes without X per row, outputs never") {
    auto c = test::compile_text("ARGUMENT X, Y\nRETURN SIN(X * 2) * COS(Y * 3) + SQRT(Y * Y + 1)");
    REQUIRE(c.model);
    const Model& m = *c.model;
    const HoistPlan plan = plan_hoisting(m.graph, {m.root}, {});
    // X*2, SIN | Y*3, COS, Y*Y, +1, SQRT: 7 operations out of the per-point tape, which
    // keeps the product and the sum.
    CHECK(plan.hoisted_operations == 7);
    REQUIRE(plan.column_nodes.size() == 1);
    CHECK(m.graph.node(plan.column_nodes[0]).op == ir::Op::Sin);
    REQUIRE(plan.row_nodes.size() == 2);
    CHECK(m.graph.node(plan.row_nodes[0]).op == ir::Op::Cos);
    CHECK(m.graph.node(plan.row_nodes[1]).op == ir::Op::Sqrt);
    const Tape tape = compile_tape(m.graph, TapeSpec{{m.root}, plan.column_nodes, plan.row_nodes});
    CHECK(tape.code.size() == 2);
    CHECK(tape.uniform_uses.size() == 2);
    // The model itself is never hoisted, even when it has no X.
    auto y_only = test::compile_text("ARGUMENT X, Y\nRETURN COS(Y * 3)");
    CHECK(plan_hoisting(y_only.model->graph, {y_only.model->root}, {}).hoisted_operations == 1);
}

TEST_CASE("in 3D, sub-expressions of X and Y (of X and Z) alone are computed once per XY (XZ) plane") {
    auto c = test::compile_text("ARGUMENT X, Y, Z\nRETURN SIN(X * Y) + COS(X - Z) * Z + Y");
    REQUIRE(c.model);
    const Model& m = *c.model;
    const HoistPlan plan = plan_hoisting(m.graph, {m.root}, {}, {.xy_planes = true, .xz_planes = true});
    // X*Y, SIN | X-Z, COS, *Z: 5 operations out of the per-point tape, which keeps the two sums.
    CHECK(plan.hoisted_operations == 5);
    CHECK(plan.column_nodes.empty());
    REQUIRE(plan.xy_plane_nodes.size() == 1);
    CHECK(m.graph.node(plan.xy_plane_nodes[0]).op == ir::Op::Sin);
    REQUIRE(plan.xz_plane_nodes.size() == 1);
    CHECK(m.graph.node(plan.xz_plane_nodes[0]).op == ir::Op::Mul);
    REQUIRE(plan.row_nodes.size() == 1);
    CHECK(m.graph.node(plan.row_nodes[0]).op == ir::Op::Arg);
    // Without planes (a 2D grid, where X and Y is every point) nothing of them is hoisted.
    CHECK(plan_hoisting(m.graph, {m.root}, {}).hoisted_operations == 0);
    // Values: tiles of whole rows (70 columns: 14 rows, the last tile of each slice 5) and
    // of one row, against the plain tape and the classic engine.
    for (int cols : {70, 1030}) {
        Grid grid = square_grid(3, 19);
        grid.x.nodes = cols;
        for (Precision precision : {Precision::Float64, Precision::Float32}) {
            const Field a = evaluate_grid(m, grid, VoxelEngine({.precision = precision}));
            CHECK(a.values == evaluate_grid(m, grid, VoxelEngine({.precision = precision, .hoist = false})).values);
            if (precision == Precision::Float64) CHECK(a.values == evaluate_grid(m, grid, engine_named("classic")).values);
        }
    }
}

TEST_CASE("known node values are read instead of computed; kept ones are written out") {
    auto c = test::compile_text("ARGUMENT X, Y\nVARIABLE D = SQRT(X*X + Y*Y)\nVARIABLE W = SIN(X * 3) * COS(Y * 5)\n"
                                "RETURN (0.5 - D) & W");
    REQUIRE(c.model);
    const Model& m = *c.model;
    REQUIRE(m.definitions.size() == 2);
    const ir::NodeId d = m.definitions[0].second, w = m.definitions[1].second;
    for (int cols : {90, 30}) {   // row tiles with hoisting, and flat tiles
        CAPTURE(cols);
        Grid grid = square_grid(2, 41);
        grid.x.nodes = cols;
        const Field whole = evaluate_grid(m, grid, engine_named("voxel"));
        std::vector<double> kept_d(grid.points()), kept_w(grid.points());
        NodeValues keep;
        keep.keep = {{d, kept_d.data()}, {w, kept_w.data()}};
        CHECK(engine_named("voxel").evaluate_grid(m.graph, m.root, grid, {}, keep).values == whole.values);
        CHECK(kept_d == evaluate_grid(m.graph, d, grid, engine_named("voxel")).values);
        CHECK(kept_w == evaluate_grid(m.graph, w, grid, engine_named("voxel")).values);
        // Known values that are not the node's own prove they are read: D := 0 everywhere.
        std::vector<double> zeros(grid.points(), 0.0);
        NodeValues known;
        known.known = {{d, zeros.data()}, {w, kept_w.data()}};
        const Field with_zero_d = engine_named("voxel").evaluate_grid(m.graph, m.root, grid, {}, known);
        auto expected = test::compile_text("ARGUMENT X, Y\nRETURN 0.5 & (SIN(X * 3) * COS(Y * 5))");
        CHECK(with_zero_d.values == evaluate_grid(*expected.model, grid, engine_named("voxel")).values);
    }
    NodeValues known;
    std::vector<double> values(9);
    known.known = {{d, values.data()}};
    CHECK_THROWS_AS(engine_named("classic").evaluate_grid(m.graph, m.root, square_grid(2, 3), {}, known),
                    std::invalid_argument);
    CHECK_THROWS_AS(engine_named("sign").evaluate_grid(m.graph, m.root, square_grid(2, 3), {}, known),
                    std::invalid_argument);
}

TEST_CASE("the engine table: names, capabilities, tuning") {
    std::vector<std::string_view> names;
    for (const Engine* e : engine_table()) names.push_back(e->name());
    CHECK(names == std::vector<std::string_view>{"classic", "voxel", "voxel-f32", "sign", "fv"});
    CHECK(engine_names(", ", " or ") == "classic, voxel, voxel-f32, sign or fv");
    CHECK(engine_names(", ", " or ", [](const EngineCapabilities& c) { return c.point; }) == "classic, voxel or voxel-f32");
    std::vector<std::string_view> exact;
    for (const Engine& e : exact_engines()) exact.push_back(e.name());
    CHECK(exact == std::vector<std::string_view>{"classic", "voxel"});
    CHECK(default_engine().name() == "voxel");
    CHECK(find_engine("gpu") == nullptr);
    CHECK_THROWS_AS(engine_named("gpu"), std::invalid_argument);
    CHECK(engine_named("classic").capabilities().expanded_tree_cost);
    CHECK_FALSE(engine_named("voxel").capabilities().expanded_tree_cost);
    CHECK(engine_named("sign").capabilities().sign_only);
    CHECK_FALSE(engine_named("sign").capabilities().point);
    // --precision float32 tunes the voxel engine into its float32 variant; classic ignores it.
    CHECK(engine_named("voxel").tuned({.precision = Precision::Float32})->name() == "voxel-f32");
    CHECK(engine_named("classic").tuned({.precision = Precision::Float32})->name() == "classic");
    const Model model = load_vm("hi.vm");
    CHECK_THROWS_AS(evaluate_point(model, {0, 0, 0}, engine_named("sign")), std::logic_error);
}
