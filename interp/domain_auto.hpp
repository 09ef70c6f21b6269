// interp/domain_auto.hpp — `--domain auto`: a box around the solid, found by interval
// subdivision.
//
// Why: a model without ranges is rendered on [-1, 1] and may show nothing. Interval
// arithmetic (interval.hpp) says for a box of space whether the model can be ≥ 0 in it; a
// search cube is halved level by level, keeping only the cells that may hold the solid, and
// the bounds of the cells left are a box that contains it (a little loose where the
// intervals are). When cells at the search cube's faces survive, the solid is unbounded (or
// larger than the cube); when none survive, it is empty. Where the intervals are too loose
// for every cube (exp/ln blends, R-operations written as formulas), the cubes are sampled on a
// lattice instead: a box of the positive nodes, not a proof (a part thinner than a step can
// lie between them).
#pragma once

#include "interp/model.hpp"

#include <array>
#include <string>
#include <variant>

namespace fortu {

/// Half-width of the largest search cube, centred at the origin (cubes of 1, 4, 16, ... are tried first).
inline constexpr double kAutoDomainSearch = 1024.0;

/// The box (one range per argument, the rest [-1, 1]), or the reason there is none
/// ("the solid reaches the search cube [-1024, 1024]³: unbounded, or larger", "the model is
/// negative everywhere in ...: the solid is empty").
std::variant<std::array<AxisRange, 3>, std::string> find_domain_auto(const Model& model);

}  // namespace fortu
