// runtime/contour.hpp — the zero contour of a 2D field (or of one slice of a 3D field) by
// marching squares, chained into polylines in world coordinates, and written as SVG
// (architecture.md "Outputs a user expects": `--contour out.svg`).
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_options.hpp"

#include <array>
#include <string>
#include <vector>

namespace fortu {

/// A chain of contour points {x, y} in world coordinates. A closed one does not repeat its
/// first point at the end.
struct Polyline {
    std::vector<std::array<double, 2>> points;
    bool closed = false;
};

/// The zero contour of one slice. A cell of four neighbouring nodes is cut where the sign
/// changes along an edge (0 counts as inside), at the linearly interpolated zero; the two
/// ambiguous saddle cases are resolved by the mean of the four corners. Cells with a
/// non-finite corner are skipped, so contours stop at invalid points. Open chains end at the
/// border of the grid or at invalid cells.
std::vector<Polyline> zero_contour(const Field& field, int slice = 0);

/// Writes the zero contour as SVG: one <polyline> per chain (a closed chain repeats its first
/// point) in the pixel coordinates of the picture of the same grid (viewBox = cols x rows,
/// node (c, r) at pixel centre (c + 0.5, r + 0.5)), with a 1.5 px black stroke, so every
/// renderer draws it alike; the world box (and a 3D slice's z) is kept in <metadata>. 3D: the
/// slice options.slice (middle by default), or every slice for a series target. Throws OutputError.
void write_contour_svg(const Field& field, const OutputTarget& target, const OutputOptions& options);

}  // namespace fortu
