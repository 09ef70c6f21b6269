// tests/fuzz/fuzz_script.cpp — libFuzzer target: any bytes as a script through the front end
// and lowering (default budgets), then an 8x8 (or 8x8x8) grid by both exact engines and the
// pruned sign renderer, which must agree: the same values from voxel and classic, and the
// sign renderer's sign wherever the value's sign is clear. A crash, a hang, an allocation
// over the fuzzer's -rss_limit_mb, or a disagreement is a finding.
#include "interp/classic_cost.hpp"
#include "interp/engine.hpp"
#include "interp/lower.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace fortu;

namespace {

// The classic engine recurses per DAG level and expands shared nodes; the command line
// refuses such runs (main.cpp), and so does this target. The operation bound is 10x below
// what the command line accepts: under the fuzzer's per-comparison hooks, a 1e5-operation
// classic walk over 64 points was a third of all the time spent, for inputs (long expanded
// chains) whose few distinct operations smaller inputs cover as well.
bool classic_can_run(const Model& model) {
    return dag_depth(model.graph, model.root) <= 20'000 && classic_operations_per_point(model.graph, model.root) <= 1e4;
}

[[noreturn]] void disagree(const char* what, std::size_t i, double a, double b) {
    std::fprintf(stderr, "fuzz_script: %s disagree at point %zu: %.17g vs %.17g\n", what, i, a, b);
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto source = std::make_shared<SourceFile>("fuzz.fortu", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    CompileOptions options;   // no INCLUDE folders: the fuzzer must not read the disk at will
    // The default budgets take ~1 s in a release build, over 10 s under the sanitizers (the
    // first timeout found, 10^9 nested FOR iterations, ran out of 'work' only then).
    options.limits.set(LimitId::work, 100'000);
    options.limits.set(LimitId::nodes, 100'000);
    std::optional<Model> model = compile(source, options, sink);
    (void)sink.render_all();
    if (!model) return 0;
    const Grid grid = model_grid(*model, grid_nodes(*model, {8}), {});
    EvalOptions eval;
    eval.threads = 1;
    const Field voxel = evaluate_grid(*model, grid, engine_named("voxel"), eval);
    if (classic_can_run(*model)) {
        const Field classic = evaluate_grid(*model, grid, engine_named("classic"), eval);
        for (std::size_t i = 0; i < voxel.values.size(); ++i) {
            const double a = voxel.values[i], b = classic.values[i];
            if (std::isnan(a) != std::isnan(b)) disagree("voxel and classic (NaN)", i, a, b);
            if (!std::isnan(a) && a != b && std::fabs(a - b) > 1e-9 * std::max(1.0, std::fabs(a))) disagree("voxel and classic", i, a, b);
        }
    }
    const Field sign = evaluate_grid(*model, grid, engine_named("sign"), eval);
    for (std::size_t i = 0; i < voxel.values.size(); ++i) {
        const double v = voxel.values[i], s = sign.values[i];
        // Only where the sign is unambiguous: far from 0 and finite.
        if (!std::isfinite(v) || std::fabs(v) < 1e-6 || std::fabs(v) > 1e300) continue;
        if (std::isnan(s)) continue;   // the renderer may not prove a sign through a NaN-prone operation
        if ((v > 0) != (s > 0)) disagree("voxel and the sign renderer", i, v, s);
    }
    return 0;
}
