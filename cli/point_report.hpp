// cli/point_report.hpp — what `fortu eval` and the REPL's `:eval` print about one point: the
// value, the exact gradient (or why there is none), the M-image normal, inside or not.
#pragma once

#include "interp/engine.hpp"
#include "interp/model.hpp"
#include "runtime/grid.hpp"

#include <array>
#include <string>

namespace fortu {

/// Four lines, each `key: ...`:
///   value: 0.25
///   gradient: -0.2 -0.4          (or: gradient: undefined (SQRT of 0))
///   normal: n1=0.1 n2=0.2 n3=0.9 n4=-0.3     (3D: n1..n5)
///   inside: yes | boundary | no | invalid
/// The normal is the FV model's (fv-method.md §1): the plane through the point and its
/// forward neighbours one step of `grid` away.
std::string point_report(const Model& model, std::array<double, 3> point, const Engine& engine, const Grid& grid);

}  // namespace fortu
