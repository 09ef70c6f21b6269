// interp/ir_print.cpp — the IR printer and the statistics `fortu ir` and `--stats` show.
#include "interp/ir_print.hpp"

#include "interp/classic_cost.hpp"
#include "interp/engine.hpp"
#include "interp/hoist.hpp"
#include "interp/voxel_engine.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>
#include <vector>

namespace fortu {

std::string format_operations(double operations) {
    if (operations >= 1e18) return fmt::format("{:.3g}", operations);
    return format_count(static_cast<std::uint64_t>(operations));
}

namespace {
std::vector<int> use_counts(const ir::Graph& graph, const std::vector<ir::NodeId>& order) {
    std::vector<int> uses(graph.size(), 0);
    for (ir::NodeId id : order) {
        const ir::Node& n = graph.node(id);
        for (int k = 0; k < ir::op_arity(n.op); ++k) ++uses[n.args[k]];
    }
    return uses;
}
}  // namespace

std::string hoisted_text(const IrStats& s) {
    if (s.hoisted_operations == 0) return "";
    return fmt::format(" ({} of them once per grid column or row on a grid of {}+ columns)",
                       format_operations(static_cast<double>(s.hoisted_operations)), kMinHoistColumns);
}

IrStats ir_stats(const Model& model) {
    IrStats s;
    const std::vector<ir::NodeId> order = model.graph.reachable(model.root);
    const std::vector<int> uses = use_counts(model.graph, order);
    s.nodes = order.size();
    for (ir::NodeId id : order) {
        if (!(ir::op_flags(model.graph.node(id).op) & ir::kLeaf)) ++s.operations;
        if (uses[id] > 1) ++s.shared;
    }
    s.reuses = model.graph.reuse_count();
    s.depth = dag_depth(model.graph, model.root);
    s.classic_operations = classic_operations_per_point(model.graph, model.root);
    s.hoisted_operations = plan_hoisting(model.graph, {model.root}, {}).hoisted_operations;
    return s;
}

std::string print_ir(const Model& model, const std::string& title) {
    const IrStats s = ir_stats(model);
    const std::vector<ir::NodeId> order = model.graph.reachable(model.root);
    const std::vector<int> uses = use_counts(model.graph, order);
    std::vector<std::size_t> number(model.graph.size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i) number[order[i]] = i;

    std::string names;
    for (const std::string& a : model.arguments) names += (names.empty() ? "" : ", ") + a;
    std::string out = fmt::format(
        "; {}\n; arguments: {}\n; nodes: {} ({} operations, {} leaves), shared: {}, "
        "hash-consing reuses: {}, depth: {}\n; voxel: {} operations per point{}\n"
        "; classic: {} operations per point\n",
        title, names, s.nodes, s.operations, s.nodes - s.operations, s.shared, s.reuses, s.depth,
        format_operations(static_cast<double>(s.operations)), hoisted_text(s), format_operations(s.classic_operations));
    for (ir::NodeId id : order) {
        const ir::Node& n = model.graph.node(id);
        std::string line = fmt::format("%{} = {}", number[id], ir::op_name(n.op));
        if (n.op == ir::Op::Const) {
            line += fmt::format(" {}", n.imm);
        } else if (n.op == ir::Op::Arg) {
            const int axis = static_cast<int>(n.imm);
            line += fmt::format(" {}", axis < static_cast<int>(model.arguments.size())
                                           ? model.arguments[axis] : std::to_string(axis));
        } else {
            for (int k = 0; k < ir::op_arity(n.op); ++k) line += fmt::format(" %{}", number[n.args[k]]);
            if (ir::op_flags(n.op) & ir::kROperation) line += fmt::format(" alpha={}", n.imm);
        }
        if (uses[id] > 1) line += fmt::format("{:>{}}; used {} times", "", line.size() < 40 ? 40 - line.size() : 1, uses[id]);
        out += line + '\n';
    }
    out += fmt::format("return %{}\n", number[model.root]);
    return out;
}

}  // namespace fortu
