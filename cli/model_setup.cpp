// cli/model_setup.cpp — compiling, grid sizing, the classic budget and the mesh checks, shared
// by the front ends.
#include "cli/model_setup.hpp"

#include "cli/option_table.hpp"
#include "interp/classic_cost.hpp"
#include "interp/grid_size.hpp"
#include "interp/ir_print.hpp"
#include "interp/vm_import.hpp"

#include <fmt/format.h>

namespace fortu {

std::optional<Model> compile_model(std::shared_ptr<const SourceFile> source, const CompileOptions& options,
                                   DiagnosticSink& sink) {
    if (is_vm_path(source->path())) {
        if (!options.constants.empty()) {   // a .vm model has no CONSTANTs to set
            sink.error({}, fmt::format("cannot set '{}': a .vm model has no CONSTANT definitions",
                                       options.constants.front().first));
            return std::nullopt;
        }
        return import_vm(std::move(source), sink);
    }
    return compile(std::move(source), options, sink);
}

std::string grid_text(const Grid& g) {
    return g.dims == 3 ? fmt::format("{}x{}x{}", g.cols(), g.rows(), g.slices())
                       : fmt::format("{}x{}", g.cols(), g.rows());
}

void check_grid_points(const Grid& grid, std::size_t max_points) {
    const double points = double(grid.cols()) * grid.rows() * grid.slices();
    if (points > double(max_points))
        throw UsageError(fmt::format("--size: {} is {} points, more than the {} fortu allocates", grid_text(grid),
                                     format_operations(points), format_operations(double(max_points))));
}

Grid request_grid(const Model& model, const std::vector<int>& size,
                  const std::array<std::optional<AxisRange>, 3>& domain, std::size_t max_points) {
    if (model.dims() == 2 && size.size() == 3)
        throw UsageError(fmt::format("--size: the model has {} argument(s); give N or WxH", model.arguments.size()));
    const Grid grid = sized_grid(model, size, domain);
    check_grid_points(grid, max_points);
    return grid;
}

std::optional<std::string> classic_refusal(const Model& model, const Engine& engine, double points, double budget) {
    if (!engine.capabilities().expanded_tree_cost) return std::nullopt;
    const int depth = dag_depth(model.graph, model.root);
    if (depth > kClassicMaxDepth)
        return fmt::format("the model is nested {} levels deep; the classic engine's recursion stops at {}\n"
                           "note: use --engine voxel", depth, kClassicMaxDepth);
    const double per_point = classic_operations_per_point(model.graph, model.root);
    const double total = per_point * points;
    if (total <= budget) return std::nullopt;
    return fmt::format(
        "the classic engine would need {} operations per point x {} points = {} operations "
        "(budget {})\nnote: use --engine voxel ({} operations per point), a smaller --size, a larger "
        "--budget, or --force",
        format_operations(per_point), format_operations(points), fmt::format("{:.3g}", total),
        fmt::format("{:.3g}", budget), format_operations(double(ir_stats(model).operations)));
}

std::optional<MeshRefusal> mesh_refusal(const Model& model, const Grid& grid) {
    if (grid.dims != 3)
        return MeshRefusal{false, fmt::format("a mesh needs a 3D model (X, Y, Z); this one has {} argument(s)",
                                              model.arguments.size())};
    if (grid.cols() < 2 || grid.rows() < 2 || grid.slices() < 2)
        return MeshRefusal{true, "a mesh needs at least 2 nodes along each axis"};
    return std::nullopt;
}

}  // namespace fortu
