// interp/grid_size.hpp — what `--size` means for a model's box: one number is the node count
// along the box's longest axis, with square cells.
//
// Why: "N nodes per axis" on a box such as 16 × 10 × 16 gives cells 1.6 times longer in Y
// than in X, and a teapot's round wall comes out an ellipse. With one number the other axes
// get as many nodes as the longest axis's cell size fits, and their ranges grow about their
// centre by less than one cell so that every cell is exactly square.
#pragma once

#include "interp/model.hpp"
#include "runtime/grid.hpp"

#include <array>
#include <optional>
#include <vector>

namespace fortu {

/// The box of the model per axis: `domain[a]` if given, else the script's range, else [-1, 1].
std::array<AxisRange, 3> model_box(const Model& model, const std::array<std::optional<AxisRange>, 3>& domain = {});

/// The ranges and node counts of `axes` (the axes to sample, e.g. {0, 1, 2} or a slice's
/// plane {1, 2}) for `size`: one number N is N nodes along the longest of them with square
/// cells (the shorter ranges widened about their centre to a whole number of cells); two or
/// three numbers are the node counts of those axes in order (the last repeated). Axes not in
/// `axes` are left as they are in `box`/`nodes`.
void size_axes(std::array<AxisRange, 3>& box, std::array<int, 3>& nodes, const std::vector<int>& axes,
               const std::vector<int>& size);

/// The grid of a run: model_grid() with `size` read as size_axes() says over the model's
/// axes (empty: RECTBMP, else 256² / 64³ as grid_nodes()).
Grid sized_grid(const Model& model, const std::vector<int>& size,
                const std::array<std::optional<AxisRange>, 3>& domain = {});

}  // namespace fortu
