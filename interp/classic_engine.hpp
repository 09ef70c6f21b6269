// interp/classic_engine.hpp — the papers' baseline: recursive R-functional evaluation.
//
// Why it exists: the papers measure iterative functional-voxel composition against this.
// For each point the RETURN expression is evaluated by recursive descent with nothing
// saved: every reference to a variable re-evaluates its definition (walking the DAG without
// memo is exactly walking the fully expanded tree), and every R-operation goes through its
// defining formula, whose getters re-evaluate an operand each time the formula references
// it. Cost per point = the expanded tree size (classic_cost.hpp), doubling per nested R0
// operation. Clean and reasonably efficient, never memoised.
#pragma once

#include "interp/engine.hpp"

#include <cstdint>

namespace fortu {

class ClassicEngine final : public Engine {
public:
    std::string_view name() const override { return "classic"; }
    std::string_view summary() const override { return "recursive per point, nothing saved (the papers' baseline)"; }
    EngineCapabilities capabilities() const override {
        return {.point = true, .gradients = true, .exact = true, .expanded_tree_cost = true};
    }
    std::unique_ptr<Engine> tuned(const EngineSettings&) const override { return std::make_unique<ClassicEngine>(); }
    Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                        const NodeValues& reuse) const override;
    PointValue evaluate_point(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point) const override;
};

/// How many nodes the classic engine evaluates for one point: the size of the expanded tree
/// (tests use it to show that nothing is saved between references).
std::uint64_t classic_node_evaluations(const ir::Graph& graph, ir::NodeId root, std::array<double, 3> point);

}  // namespace fortu
