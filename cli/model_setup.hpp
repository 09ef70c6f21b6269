// cli/model_setup.hpp — what every front end (the command line, the Python module) does
// before it evaluates: compile a model's text, size the grid a request names, refuse a
// classic run over its budget or a mesh it cannot make. One copy, so their messages and
// limits are the same.
#pragma once

#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "interp/engine.hpp"
#include "interp/lower.hpp"
#include "interp/model.hpp"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// A `.fortu` script or, by its path's extension, a `.vm` model (vm_import.hpp), which
/// takes no CompileOptions::constants (an error).
std::optional<Model> compile_model(std::shared_ptr<const SourceFile> source, const CompileOptions& options,
                                   DiagnosticSink& sink);

/// Throws UsageError when `grid` has more than `max_points` points.
void check_grid_points(const Grid& grid, std::size_t max_points = kMaxGridPoints);

/// The grid `size` and `domain` name for `model` (grid_size.hpp's sized_grid: one number is
/// the node count along the longest axis, with square cells). Throws
/// UsageError (option_table.hpp) for a 3D size on a 2D model, or more than `max_points`
/// points (`--size: 10000x10000 is 100,000,000 points, more than the 268,435,456 fortu
/// allocates`).
Grid request_grid(const Model& model, const std::vector<int>& size,
                  const std::array<std::optional<AxisRange>, 3>& domain, std::size_t max_points = kMaxGridPoints);

/// `WxH` or `WxHxD`.
std::string grid_text(const Grid& grid);

/// Why `engine` must not run `points` points of `model` (the classic engine over `budget`
/// operations or nested deeper than it recurses), with the advice note; nullopt when it may.
std::optional<std::string> classic_refusal(const Model& model, const Engine& engine, double points, double budget);

/// Why `model` cannot be meshed on `grid` (interp/mesher.hpp): a 2D model, or fewer than 2
/// nodes along an axis, which the size is to blame for (each front end names its own option).
struct MeshRefusal {
    bool size_at_fault = false;
    std::string message;   ///< without the option's name
};
std::optional<MeshRefusal> mesh_refusal(const Model& model, const Grid& grid);

}  // namespace fortu
