// interp/gradient_check.hpp — why a point has no gradient: the operation where forward-mode
// differentiation first breaks down (SQRT of 0, an R-operation where both operands vanish).
#pragma once

#include "interp/ir/ir.hpp"

#include <array>
#include <optional>
#include <string>

namespace fortu {

/// The first operation (in evaluation order) whose derivative is not finite although its
/// value and its operands' values and derivatives are.
struct UndefinedGradient {
    ir::NodeId node = ir::kNoNode;
    ir::Op op = ir::Op::Const;
    std::array<double, 3> operands{};   ///< their values (the first op_arity(op) count)
};

/// nullopt when every derivative at `point` is finite, or when a value is not finite first
/// (then the value itself is invalid and says so).
std::optional<UndefinedGradient> find_undefined_gradient(const ir::Graph& graph, ir::NodeId root,
                                                         std::array<double, 3> point);

/// "SQRT of 0", "R-conjunction of 0 and 0", "^ of 0 and 0.5".
std::string describe(const UndefinedGradient& cause);

}  // namespace fortu
