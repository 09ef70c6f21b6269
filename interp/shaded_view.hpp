// interp/shaded_view.hpp — a 3D model seen as a solid: the first surface along each view ray,
// with its normal, for a shaded picture (runtime/surface_picture.hpp).
//
// Why: a z slice says little about a solid. Casting every ray through a dense voxel grid
// would evaluate width × height × depth points; instead, as libfive's and Fidget's heightmap
// renderers do, a region (a tile of pixels × a range of depths, a box in view space) is
// evaluated once with interval arithmetic: all outside, it is skipped; all inside, its
// pixels are hit at its front; otherwise its tape is shortened for it (box_simplify.hpp,
// the same pass as the sign renderer's) and it is split, front half first, so the regions
// behind a pixel already hit are never visited. Small regions (leaves) evaluate their sample
// points with the lane kernel in float32, where SLEEF's vector exp/log make a sample several
// times cheaper than libm's float64 ones: float32 only finds each pixel's first sample at or
// inside the surface. The hit is placed between it and the sample before by the values' zero
// crossing, then refined by one Newton step along the ray from the value and gradient there
// (exact derivatives on the region's shortened tape, which keeps the zero set and the sign of
// the model, so the unit normal is the model's); the normal is that gradient. The gradients
// of a batch of hits run as float32 lanes (float_gradient.hpp), ir::Dual in float64 only
// where those are not finite or the tape has an operation without a float32 rule.
#pragma once

#include "interp/engine.hpp"
#include "interp/model.hpp"
#include "runtime/surface_picture.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace fortu {

/// The direction the solid is seen from, in degrees: azimuth about the `up` axis and
/// elevation above the plane across it (90: the top). With Y up (the default: RANOK's
/// scripts and the Prospero models stand on Y) front is from +Z and side from +X; with Z up,
/// front is from −Y and side from +X; with X up, front is from −Z and side from +Y.
struct ViewDirection {
    double azimuth = 0.0;
    double elevation = 0.0;
    int up = 1;   ///< the axis drawn upwards: 0 X, 1 Y, 2 Z
};

/// What one shaded view evaluated (for --stats and tests).
struct ShadedViewStats {
    std::size_t leaves = 0;            ///< leaf regions whose samples ran
    std::size_t compiled_leaves = 0;   ///< of them, those that ran on compiled tapes
    std::size_t tapes_compiled = 0;    ///< leaf tapes compiled (by all workers)
};

/// `top`, `front`, `side`, `iso` (azimuth 45, elevation 35.26) or `AZ,EL` in degrees;
/// nullopt when malformed.
std::optional<ViewDirection> parse_view_direction(const std::string& text);

/// Renders `root` (of X, Y, Z) clipped to `box` as seen from `view`, orthographically, on a
/// width × height picture with square pixels that fits the box's outline. Depth is sampled
/// at one pixel's spacing. With `compile` (not --no-jit) the leaves' tapes that recur run as
/// machine code (compiled_tape_cache.hpp): the same picture, bit for bit.
SurfaceImage render_shaded_view(const ir::Graph& graph, ir::NodeId root, const std::array<AxisRange, 3>& box,
                                const ViewDirection& view, int width, int height, const EvalOptions& options = {},
                                bool compile = true, ShadedViewStats* stats = nullptr);

}  // namespace fortu
