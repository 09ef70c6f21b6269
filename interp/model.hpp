// interp/model.hpp — a checked, lowered FORTU model: the IR DAG, its root, its arguments
// and what the script says about its domain. Produced by compile() (lower.hpp); consumed
// by the engines and the command line.
#pragma once

#include "grammar/source.hpp"
#include "interp/ir/ir.hpp"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fortu {

/// The R-system that `&` and `|` follow (spec §3): alpha = 0 is R0, alpha = 1 is
/// R1 = MINMAX, alpha in (-1, 1) is R_alpha.
struct RSystem {
    double alpha = 0.0;
    std::string name() const;
};

/// Parses `r0`, `minmax`, `r1`, `alpha=A` (case-insensitive); nullopt when malformed or A
/// is outside (-1, 1].
std::optional<RSystem> parse_rsystem(const std::string& text);

struct AxisRange {
    double min = -1.0;
    double max = 1.0;
};

struct Model {
    ir::Graph graph;
    ir::NodeId root = ir::kNoNode;
    std::vector<std::string> arguments;                      ///< 1..3 names, in order
    std::array<std::optional<AxisRange>, 3> ranges;          ///< per argument, from the script
    std::optional<std::array<int, 2>> raster;                ///< RECTBMP(width, height)
    /// Set when `ranges` come from the RANOK header comment (header_domain.hpp): the note,
    /// rendered, that a run prints unless --domain replaces them.
    std::string domain_note;
    /// Each top-level CONSTANT/VARIABLE definition whose value is an operation (name, node),
    /// in script order: the cells whose values the REPL keeps between evaluations.
    std::vector<std::pair<std::string, ir::NodeId>> definitions;

    int dims() const { return arguments.size() == 3 ? 3 : 2; }
};

}  // namespace fortu
