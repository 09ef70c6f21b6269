// interp/engine.cpp — what every engine shares: looking engines up in the table, the
// entry points callers use, and the grid a run samples. Knows no engine by name.
#include "interp/engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fortu {

PointValue Engine::evaluate_point(const ir::Graph&, ir::NodeId, std::array<double, 3>) const {
    throw std::logic_error(std::string("the ") + std::string(name()) + " engine evaluates whole grids only");
}

const Engine* find_engine(std::string_view name) {
    for (const Engine* engine : engine_table())
        if (engine->name() == name) return engine;
    return nullptr;
}

const Engine& engine_named(std::string_view name) {
    if (const Engine* engine = find_engine(name)) return *engine;
    throw std::invalid_argument("unknown engine '" + std::string(name) + "'");
}

std::string engine_names(std::string_view separator, std::string_view last_separator,
                         const std::function<bool(const EngineCapabilities&)>& filter) {
    std::vector<std::string_view> names;
    for (const Engine* engine : engine_table())
        if (!filter || filter(engine->capabilities())) names.push_back(engine->name());
    std::string text;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0) text += i + 1 == names.size() ? last_separator : separator;
        text += names[i];
    }
    return text;
}

std::string engine_summaries() {
    std::string text;
    for (const Engine* engine : engine_table())
        text += fmt::format("\n  {:<12}{}", engine->name(), engine->summary());
    return text;
}

std::vector<std::reference_wrapper<const Engine>> exact_engines() {
    std::vector<std::reference_wrapper<const Engine>> engines;
    for (const Engine* engine : engine_table())
        if (engine->capabilities().exact) engines.push_back(*engine);
    return engines;
}

Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const Engine& engine,
                    const EvalOptions& options) {
    return engine.evaluate_grid(graph, root, grid, options, {});
}

Field evaluate_grid(const Model& model, const Grid& grid, const Engine& engine, const EvalOptions& options) {
    return engine.evaluate_grid(model.graph, model.root, grid, options, {});
}

PointValue evaluate_point(const Model& model, std::array<double, 3> point, const Engine& engine) {
    return engine.evaluate_point(model.graph, model.root, point);
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
