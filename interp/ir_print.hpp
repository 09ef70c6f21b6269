// interp/ir_print.hpp — `fortu ir`: the lowered DAG as text, with its size and sharing.
#pragma once

#include "interp/model.hpp"

#include <cstddef>
#include <string>

namespace fortu {

struct IrStats {
    std::size_t nodes = 0;        ///< nodes reachable from RETURN
    std::size_t operations = 0;   ///< of which non-leaf (what the voxel engine computes per point)
    std::size_t shared = 0;       ///< nodes used by more than one node (computed once, used many times)
    std::size_t reuses = 0;       ///< times lowering asked for a node that already existed
    int depth = 0;                ///< longest operand chain
    double classic_operations = 0;  ///< classic engine, per point
    std::size_t hoisted_operations = 0;  ///< of `operations`, done per grid column or row instead (hoist.hpp)
};

IrStats ir_stats(const Model& model);
/// " (N of them once per grid column or row ...)", or "" when nothing is hoisted.
std::string hoisted_text(const IrStats& stats);

/// The header (counts) followed by one line per node: `%id = op operands`.
std::string print_ir(const Model& model, const std::string& title);

/// `397,393,719`, or `1.2e+21` when too large to be exact.
std::string format_operations(double operations);

}  // namespace fortu
