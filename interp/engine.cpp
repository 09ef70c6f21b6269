// interp/engine.cpp — engine selection and the entry points shared by both engines.
#include "interp/engine.hpp"

#include "interp/classic_engine.hpp"
#include "interp/voxel_engine.hpp"

#include <algorithm>
#include <cmath>

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

int dag_depth(const ir::Graph& graph, ir::NodeId root) {
    std::vector<int> depth(graph.size(), 1);
    for (ir::NodeId id : graph.reachable(root)) {
        const ir::Node& n = graph.node(id);
        for (int k = 0; k < ir::op_arity(n.op); ++k) depth[id] = std::max(depth[id], depth[n.args[k]] + 1);
    }
    return depth[root];
}

}  // namespace fortu
