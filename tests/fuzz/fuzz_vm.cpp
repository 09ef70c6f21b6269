// tests/fuzz/fuzz_vm.cpp — libFuzzer target: any bytes as a Prospero .vm model through the
// importer, then an 8x8 grid by the voxel engine.
#include "interp/engine.hpp"
#include "interp/vm_import.hpp"

#include <cstdint>
#include <string>

using namespace fortu;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto source = std::make_shared<SourceFile>("fuzz.vm", std::string(reinterpret_cast<const char*>(data), size));
    DiagnosticSink sink;
    std::optional<Model> model = import_vm(source, sink);
    (void)sink.render_all();
    if (!model) return 0;
    EvalOptions eval;
    eval.threads = 1;
    (void)evaluate_grid(*model, model_grid(*model, grid_nodes(*model, {8}), {}), engine_named("voxel"), eval);
    return 0;
}
