// tests/unit/interp_test_support.hpp — compiling model text and model files in tests.
#pragma once

#include "grammar/diagnostic.hpp"
#include "interp/engine.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/lower.hpp"
#include "interp/tape.hpp"
#include "interp/vm_import.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace fortu::test {

struct Compiled {
    std::optional<Model> model;
    DiagnosticSink sink;
    std::shared_ptr<SourceFile> source;
};

inline Compiled compile_text(const std::string& text, const CompileOptions& options = {},
                             const std::string& path = "test.fortu") {
    Compiled c;
    c.source = std::make_shared<SourceFile>(path, text);
    c.model = compile(c.source, options, c.sink);
    return c;
}

/// A .fortu script (with the shipped stdlib) or a .vm model from a file; nullopt when it
/// cannot be read or compiled.
inline std::optional<Model> load_model_file(const std::filesystem::path& path) {
    std::string error;
    auto source = SourceFile::load(path.string(), error);
    if (!source) return std::nullopt;
    DiagnosticSink sink;
    CompileOptions options;
    options.include_dirs = {std::string(FORTU_SOURCE_DIR) + "/stdlib"};
    return is_vm_path(path.string()) ? import_vm(source, sink) : compile(source, options, sink);
}

/// The root's values at `points` ({X, Y} or {X, Y, Z}) by the lane kernel, every slot a
/// lane array.
template <std::size_t N>
std::vector<double> run_tape(const Tape& tape, const std::vector<std::array<double, N>>& points) {
    const int n = static_cast<int>(points.size());
    std::vector<double> lanes(std::size_t(tape.slot_count) * n, 0.0);
    std::vector<double*> slots(tape.slot_count);
    for (std::size_t k = 0; k < slots.size(); ++k) slots[k] = lanes.data() + k * n;
    for (auto [slot, axis] : tape.arguments)
        for (int l = 0; l < n; ++l) slots[slot][l] = std::size_t(axis) < N ? points[l][axis] : 0.0;
    for (auto [slot, value] : tape.constants) std::fill_n(slots[slot], n, value);
    run_lanes<double, 0>(tape.code.data(), tape.code.size(), slots.data(), n);
    return std::vector<double>(slots[tape.root_slot], slots[tape.root_slot] + n);
}

/// The value of a model at a point with the given engine (the model must compile).
inline double value_at(const std::string& text, double x = 0, double y = 0, double z = 0,
                       const Engine& engine = engine_named("voxel")) {
    Compiled c = compile_text(text);
    if (!c.model) throw std::runtime_error(c.sink.render_all());
    return evaluate_point(*c.model, {x, y, z}, engine).value;
}

}  // namespace fortu::test
