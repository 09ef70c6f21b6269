// interp/engine.cpp — engine selection and the entry points shared by both engines.
#include "interp/engine.hpp"

#include "interp/classic_engine.hpp"
#include "interp/voxel_engine.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fortu {

std::optional<EngineKind> parse_engine(const std::string& name) {
    if (name == "classic") return EngineKind::Classic;
    if (name == "voxel") return EngineKind::Voxel;
    return std::nullopt;
}

const char* engine_name(EngineKind kind) {
    return kind == EngineKind::Classic ? "classic" : "voxel";
}

Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, EngineKind engine,
                    const EvalOptions& options) {
    Field field;
    field.grid = grid;
    field.values.assign(grid.points(), std::nan(""));
    if (engine == EngineKind::Classic && !(options.known.empty() && options.keep.empty()))
        throw std::invalid_argument("known and kept node values are the voxel engine's (the classic engine saves nothing)");
    if (engine == EngineKind::Classic) classic_evaluate_grid(graph, root, field, options);
    else voxel_evaluate_grid(graph, root, field, options);
    return field;
}

Field evaluate_grid(const Model& model, const Grid& grid, EngineKind engine, const EvalOptions& options) {
    return evaluate_grid(model.graph, model.root, grid, engine, options);
}

PointValue evaluate_point(const Model& model, std::array<double, 3> point, EngineKind engine) {
    return engine == EngineKind::Classic ? classic_evaluate_point(model.graph, model.root, point)
                                         : PointEvaluator(model.graph, model.root)(point);
}

std::array<int, 3> grid_nodes(const Model& model, const std::vector<int>& size) {
    std::array<int, 3> nodes{256, 256, 1};
    if (model.dims() == 3) nodes = {64, 64, 64};
    if (model.raster) nodes = {(*model.raster)[0], (*model.raster)[1], 1};
    if (!size.empty())
        for (std::size_t a = 0; a < 3; ++a) nodes[a] = size[std::min(a, size.size() - 1)];
    return nodes;
}

Grid model_grid(const Model& model, std::array<int, 3> nodes,
                const std::array<std::optional<AxisRange>, 3>& domain) {
    Grid grid;
    grid.dims = model.dims();
    Axis* axes[3] = {&grid.x, &grid.y, &grid.z};
    const int axis_count = static_cast<int>(model.arguments.size());
    if (grid.dims == 2) nodes[2] = 1;
    if (axis_count == 1) nodes[1] = 1;
    for (int a = 0; a < 3; ++a) {
        AxisRange r{-1.0, 1.0};
        if (a < axis_count && model.ranges[a]) r = *model.ranges[a];
        if (domain[a]) r = *domain[a];
        axes[a]->min = r.min;
        axes[a]->max = r.max;
        axes[a]->nodes = nodes[a];
    }
    return grid;
}

int dag_depth(const ir::Graph& graph, ir::NodeId root) {
    std::vector<int> depth(graph.size(), 1);
    for (ir::NodeId id : graph.reachable(root)) {
        const ir::Node& n = graph.node(id);
        for (int k = 0; k < ir::op_arity(n.op); ++k) depth[id] = std::max(depth[id], depth[n.args[k]] + 1);
    }
    return depth[root];
}

}  // namespace fortu
