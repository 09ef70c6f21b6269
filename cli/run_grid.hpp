// cli/run_grid.hpp — the grid a command evaluates, from the model and the grid options:
// the domain (--domain, --domain auto, the script, its RANOK header comment, with the note
// saying when the comment decides), --size (one number: square cells), and --slice (one
// plane of a 3D model, of any size, instead of the cube); and what a 3D picture shows (a
// shaded view of the solid unless a slice or a series of slices is asked for).
#pragma once

#include "cli/cli_options.hpp"
#include "interp/shaded_view.hpp"
#include "runtime/field.hpp"
#include "runtime/grid.hpp"

#include <array>

namespace fortu {

/// The grid of a run. Throws UsageError: a WxH size on a 3D model without --slice, a slice
/// outside the domain, --slice on a 2D model, more points than fortu allocates, or
/// --domain auto without an answer.
Grid run_grid(const Model& model, const CliOptions& o);

/// The model's box after --domain / --domain auto / the script (as run_grid uses it).
std::array<AxisRange, 3> run_box(const Model& model, const CliOptions& o);

/// True when `-o` of this run is a picture of a 3D model to draw as a shaded view.
bool wants_shaded_view(const Model& model, const CliOptions& o);

/// The picture size of a shaded view: --size N (N×N) or WxH; default 512×512.
std::array<int, 2> view_size(const CliOptions& o);

/// The z slice number of `cube` that `slice` names (an index, or the nearest node to z=V);
/// throws UsageError for an x or y plane or a slice outside the grid (fortu singular).
int z_slice_number(const Grid& cube, const SliceChoice& slice);

/// A field of an x or y plane (one node along that axis) as the 2D field a picture shows:
/// columns along the plane's first remaining axis, rows along Z (top = largest Z). Other
/// fields are returned as they are.
Field plane_picture(const Field& field);

}  // namespace fortu
