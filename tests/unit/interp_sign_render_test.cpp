// tests/unit/interp_sign_render_test.cpp — the acceptance test of interval-pruned rendering:
// its sign image equals the sign of the full float64 evaluation pixel for pixel, on every
// example and every .vm model (256² in 2D, 64³ in 3D), and every RANOK script (160², 40³).
#include "interp_test_support.hpp"

#include "interp/ir/kernels.hpp"
#include "interp/sign_render.hpp"
#include "interp/vm_import.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <stdexcept>
#include <string>

using namespace fortu;

namespace {

Grid grid_for(const Model& model, int nodes_2d, int nodes_3d) {
    return model_grid(model, model.dims() == 3 ? std::array<int, 3>{nodes_3d, nodes_3d, nodes_3d}
                                               : std::array<int, 3>{nodes_2d, nodes_2d, 1});
}

std::optional<Model> load(const std::filesystem::path& path, std::string& errors) {
    std::string error;
    auto source = SourceFile::load(path.string(), error);
    if (!source) { errors = error; return std::nullopt; }
    DiagnosticSink sink;
    CompileOptions options;
    options.include_dirs = {std::string(FORTU_SOURCE_DIR) + "/stdlib"};
    auto model = is_vm_path(path.string()) ? import_vm(source, sink) : compile(source, options, sink);
    errors = sink.render_all();
    return model;
}

/// Number of grid points where the pruned sign differs from the full evaluation's sign
/// (with `except_rounded_zero`: not counting points where the full value is exactly 0, the
/// documented exception in sign_render.hpp).
std::size_t sign_mismatches(const Model& model, const Grid& grid, SignRenderStats* stats = nullptr,
                            bool except_rounded_zero = false) {
    const Field full = evaluate_grid(model, grid, engine_named("voxel"));
    const Field sign = sign_render(model.graph, model.root, grid, {}, stats);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < full.values.size(); ++i) {
        const double expected = ir::k_sign(full.values[i]);
        const double got = sign.values[i];
        if (except_rounded_zero && full.values[i] == 0.0 && (got == 1.0 || got == -1.0)) continue;
        if (!(expected == got || (std::isnan(expected) && std::isnan(got)))) ++bad;
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

/// Compares the two renderers on every file; returns the names of the files that did not
/// compile (each caller states which those are, so none is skipped silently).
std::vector<std::string> check_all(const std::vector<std::filesystem::path>& files, bool except_rounded_zero = false,
                                   int nodes_2d = 256, int nodes_3d = 64) {
    REQUIRE(!files.empty());
    std::vector<std::string> not_compiled;
    for (const auto& path : files) {
        CAPTURE(path.string());
        std::string errors;
        std::optional<Model> model = load(path, errors);
        if (!model) {
            not_compiled.push_back(path.filename().string());
            continue;
        }
        CHECK(sign_mismatches(*model, grid_for(*model, nodes_2d, nodes_3d), nullptr, except_rounded_zero) == 0);
    }
    return not_compiled;
}

}  // namespace

TEST_CASE("pruned sign images equal full evaluation on every .vm model") {
    CHECK(check_all(files_in(std::filesystem::path(FORTU_SHARED_DIR) / "data", ".vm")) == std::vector<std::string>{});
}

TEST_CASE("pruned sign images equal full evaluation on every example, up to rounded zeros") {
    // Polygon examples (lrfm_polygon14, s1_fig3a_formula, singular_pentagon) have vertices and
    // sides through grid nodes: there the full R0 formula rounds to exactly 0 and the pruned
    // renderer gives the sign of the rounding residue (sign_render.hpp, the one exception).
    CHECK(check_all(files_in(std::filesystem::path(FORTU_SOURCE_DIR) / "examples", ".fortu"), true) ==
          std::vector<std::string>{});
}

TEST_CASE("pruned sign images equal full evaluation on every RANOK script, up to rounded zeros") {
    // new_1_new.fortu: polygon sides W_k pass exactly through grid nodes; there W_k is a
    // rounding residue (~1e-15) next to an operand ~5, the full R0 formula rounds the
    // result to 0 and the pruned renderer gives the residue's sign.
    // 160² / 40³: the 56 scripts at a size the sanitizer build runs in reasonable time.
    CHECK(check_all(files_in(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "ranok-scripts", ".fortu"), true, 160,
                    40) == std::vector<std::string>{});
    std::string errors;
    auto model = load(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "ranok-scripts" / "new_1_new.fortu", errors);
    REQUIRE(model);
    CHECK(sign_mismatches(*model, grid_for(*model, 256, 64)) == 35);
}

TEST_CASE("pruning decides most of prospero.vm without touching its points") {
    std::string errors;
    auto model = load(std::filesystem::path(FORTU_SHARED_DIR) / "data" / "prospero.vm", errors);
    REQUIRE(model);
    SignRenderStats stats;
    const Grid grid = grid_for(*model, 512, 64);
    CHECK(sign_mismatches(*model, grid, &stats) == 0);
    CHECK(stats.decided_points + stats.leaf_points == grid.points());
    // Over a quarter of the image is decided by intervals alone (16×16 leaves along the text
    // take the rest), and the tapes at the leaves keep a few dozen of the 6361 operations
    // (41 per point on average).
    CHECK(stats.decided_points > grid.points() / 4);
    CHECK(stats.leaf_operations < stats.leaf_points * 100);
    // The leaves run in float32 within a proven bound (float32_bound.hpp): only a few leaves
    // (around circle centres, where SQRT's operand nears 0) fall back to float64.
    CHECK(stats.float64_leaves * 20 < stats.leaf_points / 256);
}

TEST_CASE("R-operations collapse for the sign: a 64-segment R0 contour") {
    // f_k = distance sum to the ends of segment k minus its length, R0-intersected: no
    // min/max anywhere, so only the sign rules can shorten the tape.
    std::string text = "ARGUMENT x(-1, 1), y(-1, 1);\nRETURN !(";
    for (int k = 0; k < 64; ++k) {
        const double a0 = 2 * M_PI * k / 64, a1 = 2 * M_PI * (k + 1) / 64;
        text += fmt::format("{5}(SQRT((x-{0})^2+(y-{1})^2) + SQRT((x-{2})^2+(y-{3})^2) - {4} - 0.01)",
                            0.8 * std::cos(a0), 0.8 * std::sin(a0), 0.8 * std::cos(a1), 0.8 * std::sin(a1),
                            0.8 * std::hypot(std::cos(a0) - std::cos(a1), std::sin(a0) - std::sin(a1)), k ? " & " : "");
    }
    text += ");\n";
    test::Compiled c = test::compile_text(text);
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    SignRenderStats stats;
    const Grid grid = grid_for(*c.model, 200, 0);
    CHECK(sign_mismatches(*c.model, grid, &stats) == 0);
    const double full_ops = double(c.model->graph.reachable(c.model->root).size());
    CHECK(double(stats.leaf_operations) < 0.25 * full_ops * double(stats.leaf_points));
}

TEST_CASE("NaN and infinity: the sign image marks invalid points as the full evaluation does") {
    // SQRT of a negative number is NaN on the left half; 1/X is ±inf at X = 0 (a grid node).
    test::Compiled c = test::compile_text("ARGUMENT x(-1, 1), y(-1, 1);\nRETURN SQRT(x) - 0.5 + 1/x - 1/x + (0.3 - y) * 0;\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    Grid g = grid_for(*c.model, 65, 0);
    CHECK(sign_mismatches(*c.model, g) == 0);
    const Field s = sign_render(c.model->graph, c.model->root, g);
    CHECK(std::isnan(s.values[g.index(0, 0)]));
    CHECK(std::isnan(s.values[g.index(32, 10)]));   // X = 0: inf - inf
    CHECK(s.values[g.index(64, 10)] == 1.0);        // X = 1: 1 - 0.5
    CHECK(s.values[g.index(40, 10)] == 0.0);        // X = 0.25: 0.5 - 0.5 + 4 - 4 + 0
}

namespace {

/// A model's signs both ways, the float64 Field and the int8 SignVolume, and at how many nodes
/// they differ (NaN equals kNaN).
struct BothSigns {
    Grid grid;
    Field field;
    SignVolume volume;
    std::size_t differing = 0;
};

BothSigns both_signs(const std::string& text, int nodes_2d, int nodes_3d) {
    test::Compiled c = test::compile_text(text);
    if (!c.model) throw std::runtime_error(c.sink.render_all());
    BothSigns s{grid_for(*c.model, nodes_2d, nodes_3d), {}, {}, 0};
    s.field = sign_render(c.model->graph, c.model->root, s.grid);
    s.volume = sign_render_volume(c.model->graph, c.model->root, s.grid);
    if (s.volume.codes.size() != s.grid.points()) throw std::runtime_error("volume of the wrong size");
    for (std::size_t i = 0; i < s.grid.points(); ++i) {
        const double a = s.field.values[i];
        const int8_t b = s.volume.sign(i);
        s.differing += std::isnan(a) ? b != SignVolume::kNaN : b != a;
    }
    return s;
}

}  // namespace

TEST_CASE("a 3D sign volume keeps one int8 per node: the same signs and statistics as the float64 field") {
    // NaN where x < 0 (SQRT), +1, −1 and exact zeros (z = 0.5 on a grid node) all occur.
    const BothSigns s = both_signs(
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN SQRT(x) * 0 + (0.5 - z) * (0.6 - x*x - y*y);\n", 0, 17);
    const Grid& g = s.grid;
    const Field& field = s.field;
    const SignVolume& volume = s.volume;
    CHECK(s.differing == 0);
    const Field expanded = volume.expanded();
    std::size_t expanded_differing = 0;
    for (std::size_t i = 0; i < g.points(); ++i) {
        const double a = field.values[i], b = expanded.values[i];
        expanded_differing += !(a == b || (std::isnan(a) && std::isnan(b)));
    }
    CHECK(expanded_differing == 0);
    CHECK(volume.sign(g.index(0, 0, 0)) == SignVolume::kNaN);
    CHECK(volume.sign(g.index(16, 8, 0)) == -1);   // x = 1, y = 0, z = −1: (1.5)(−0.4)
    CHECK(volume.sign(g.index(12, 8, 12)) == 0);   // z = 0.5
    const FieldStats a = field_stats(field), b = volume.stats();
    CHECK(a.invalid == b.invalid);
    CHECK(a.positive == b.positive);
    CHECK(a.zero == b.zero);
    CHECK(a.negative == b.negative);
    CHECK(a.min == b.min);
    CHECK(a.max == b.max);
    CHECK(a.mean == b.mean);
    CHECK(b.invalid > 0);
    CHECK(b.positive > 0);
    CHECK(b.zero > 0);
    CHECK(b.negative > 0);
}

TEST_CASE("a 2D sign image kept as int8: every sign of 16-wide leaf rows as the float64 field") {
    // +1, −1 and exact zeros (y = 0.25 on a grid node) in 16-wide leaf rows, which the int8
    // leaves store 16 lanes at a time; NaN where x < 0 (SQRT), in boxes that run in float64
    // (NaN lanes of the vector store: tests/unit/interp_stored_sign_test.cpp).
    const BothSigns s = both_signs(
        "ARGUMENT x(-1, 1), y(-1, 1);\nRETURN SQRT(x) * 0 + (0.25 - y) * (0.6 - x*x - y*y);\n", 129, 0);
    const Grid& g = s.grid;
    const SignVolume& image = s.volume;
    std::size_t counts[4] = {};
    for (std::size_t i = 0; i < g.points(); ++i) ++counts[image.sign(i) == SignVolume::kNaN ? 3 : image.sign(i) + 1];
    CHECK(s.differing == 0);
    CHECK(image.sign(g.index(0, 0)) == SignVolume::kNaN);
    REQUIRE(g.y_at(48) == 0.25);                     // rows go down from y = 1
    CHECK(image.sign(g.index(80, 48)) == 0);        // y = 0.25
    CHECK(image.sign(g.index(80, 64)) == 1);        // x = 0.25, y = 0: 0.25 · 0.5375
    CHECK(image.sign(g.index(128, 64)) == -1);      // x = 1, y = 0: 0.25 · (−0.4)
    CHECK(counts[0] > 0);
    CHECK(counts[1] > 0);
    CHECK(counts[2] > 0);
    CHECK(counts[3] > 0);
}

TEST_CASE("the volume starts outside: boxes decided inside, on the boundary or NaN are still written") {
    // Inside everywhere (every box decided +1), outside everywhere (nothing written after the
    // start), and a thick shell around a cavity (both signs decided, leaves between).
    const char* models[] = {
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN 1 + x*x + y*y + z*z;\n",
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN -1 - x*x - y*y - z*z;\n",
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN MIN(2.56 - x*x - y*y - z*z, x*x + y*y + z*z - 0.09);\n",
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN (x*x + y*y + z*z) * 0;\n",
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN SQRT(-1 - x*x);\n",
    };
    for (int m = 0; m < 5; ++m) {
        CAPTURE(m);
        test::Compiled c = test::compile_text(models[m]);
        REQUIRE_MESSAGE(c.model, c.sink.render_all());
        const Grid g = grid_for(*c.model, 0, 33);
        SignRenderStats stats;
        CHECK(sign_mismatches(*c.model, g, &stats) == 0);
        const SignVolume volume = sign_render_volume(c.model->graph, c.model->root, g);
        const FieldStats s = volume.stats();
        if (m == 0) CHECK(s.positive == g.points());
        if (m == 1) CHECK(s.negative == g.points());
        if (m < 2) CHECK(stats.leaf_points == 0);  // decided by intervals alone
        if (m == 2) {
            // Counted apart (x² + y² + z² > 2.56 or < 0.09 over the 33³ nodes, step 1/16):
            // the 8 corners and the cavity are outside, no node is on the boundary.
            CHECK(s.negative == 645);
            CHECK(s.positive == 35292);
            CHECK(stats.decided_points > g.points() / 2);
        }
        if (m == 3) CHECK(s.zero == g.points());
        if (m == 4) CHECK(s.invalid == g.points());
    }
}

TEST_CASE("a sign volume stores ~sign: outside is a zero byte, so fresh zeroed pages need no background pass") {
    CHECK(SignVolume::code_of(-1) == 0);
    CHECK(SignVolume::code_of(0) == -1);
    CHECK(SignVolume::code_of(1) == -2);
    CHECK(SignVolume::code_of(SignVolume::kNaN) == 127);
    // Outside everywhere over 65³ nodes (past one 4 KiB page) and 129³ (past 2 MiB): every
    // code is the untouched zero, and decodes to −1.
    test::Compiled c = test::compile_text("ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN -1 - x*x - y*y - z*z;\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    for (int n : {65, 129}) {
        CAPTURE(n);
        const Grid g = grid_for(*c.model, 0, n);
        const SignVolume volume = sign_render_volume(c.model->graph, c.model->root, g);
        REQUIRE(volume.codes.size() == g.points());
        CHECK(std::count(volume.codes.begin(), volume.codes.end(), int8_t{0}) == std::ptrdiff_t(g.points()));
        CHECK(volume.sign(g.points() - 1) == -1);
        CHECK(volume.stats().negative == g.points());
    }
}

TEST_CASE("a sign volume past 2 MiB counts its statistics as the float64 field does") {
    // 129³ nodes: 2,146,689 signs, many blocks of the vectorised count and a tail.
    test::Compiled c = test::compile_text(
        "ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN SQRT(x + 0.5) * 0 + (0.5 - z) * (0.6 - x*x - y*y);\n");
    REQUIRE_MESSAGE(c.model, c.sink.render_all());
    const Grid g = grid_for(*c.model, 0, 129);
    const SignVolume volume = sign_render_volume(c.model->graph, c.model->root, g);
    REQUIRE(volume.codes.size() == 2146689);
    const FieldStats a = field_stats(volume.expanded()), b = volume.stats();
    CHECK(a.invalid == b.invalid);
    CHECK(a.positive == b.positive);
    CHECK(a.zero == b.zero);
    CHECK(a.negative == b.negative);
    CHECK(a.mean == b.mean);
    CHECK(b.invalid == 32 * 129 * 129);   // x < -0.5: the 32 first columns
    CHECK(b.zero == 97 * 129);            // z = 0.5 where x ≥ -0.5
}

TEST_CASE("a cancelled sign render reads NaN everywhere: no unreached node passes for outside") {
    // A disc and a ball: inside and outside both decided, so a finished render has no NaN.
    const std::atomic<bool> cancelled{true};
    EvalOptions options;
    options.cancel = &cancelled;
    test::Compiled disc = test::compile_text("ARGUMENT x(-1, 1), y(-1, 1);\nRETURN 0.5 - x*x - y*y;\n");
    REQUIRE_MESSAGE(disc.model, disc.sink.render_all());
    const Grid plane = grid_for(*disc.model, 33, 0);
    CHECK(field_stats(sign_render(disc.model->graph, disc.model->root, plane, options)).invalid == plane.points());
    CHECK(field_stats(sign_render(disc.model->graph, disc.model->root, plane)).invalid == 0);
    test::Compiled ball = test::compile_text("ARGUMENT x(-1, 1), y(-1, 1), z(-1, 1);\nRETURN 0.5 - x*x - y*y - z*z;\n");
    REQUIRE_MESSAGE(ball.model, ball.sink.render_all());
    const Grid cube = grid_for(*ball.model, 0, 17);
    CHECK(sign_render_volume(ball.model->graph, ball.model->root, cube, options).stats().invalid == cube.points());
    CHECK(sign_render_volume(ball.model->graph, ball.model->root, cube).stats().invalid == 0);
}
