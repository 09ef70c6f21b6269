// runtime/output_options.hpp — the choices a user can make about output files, shared by all
// writers (output.hpp dispatches on the file extension).
#pragma once

#include "runtime/palette.hpp"

#include <array>
#include <string>
#include <vector>

namespace fortu {

/// How a picture's values map to colours (picture.hpp's ColourScale): each side by its own
/// 99th percentile (Auto), one percentile for both signs (Symmetric), or Fixed: outside
/// saturates at `low` (< 0), inside at `high` (> 0).
struct ScaleChoice {
    enum class Mode { Auto, Symmetric, Fixed };
    Mode mode = Mode::Auto;
    double low = -1.0, high = 1.0;
};

/// What a picture shows beside the colours: `--scale`, `--levels`, `--legend`.
struct PictureStyle {
    ScaleChoice scale;
    /// Iso-lines: `level_count` per side, evenly spaced up to where the colour saturates, or
    /// the values in `levels` when it is not empty. The zero contour stays black.
    int level_count = 0;
    std::vector<double> levels;
    /// A colour bar with tick values below or right of the picture, the axes' ranges and
    /// the slice's position.
    bool legend = false;
    /// The legend's names of the picture's horizontal and vertical axes, and the plane a 3D
    /// slice lies in when the grid does not say it (`x = 0.3` for an x plane shown with Z up).
    std::string axes = "xy";
    std::string plane;
};

struct OutputOptions {
    /// 3D, picture and SVG formats: the z slice drawn (0 = smallest Z); −1 = the middle one.
    /// A picture path with a number conversion (`slice_%03d.png`) writes every slice instead.
    int slice = -1;
    /// npy: little-endian float32 (`<f4`) instead of float64 (`<f8`).
    bool npy_float32 = false;
    /// npy of a 3D grid: also write NAME.npy.json with the first node and steps (what a
    /// user's run does; golden references go without).
    bool npy_sidecar = false;
    /// Pictures: draw the zero contour in black.
    bool draw_contour = true;
    /// Pictures: shading bands, this many per unit of the colour scale (0 = none).
    int bands = 0;
    /// JPEG quality, 1..100.
    int jpeg_quality = 95;
    /// write_mimages() to a picture series: the papers' 8-bit grey palette (P = 256) or the
    /// 24-bit RGB one (P = 2^24), fv-method.md §1.1 item 5.
    Palette mimage_palette = Palette::Grey8;
    /// Pictures: points {x, y} in world coordinates to mark with a red ring (singular
    /// points, probes); points outside the domain are skipped.
    std::vector<std::array<double, 2>> markers;
    /// Pictures: scale, iso-lines and legend.
    PictureStyle picture;
    /// Meshes: ASCII STL instead of binary.
    bool ascii = false;
    /// Volume formats that can hold them (.vti): add the FV model's components n1.. as
    /// point data (`--mimages m.vti`).
    bool mimages = false;
    /// .vdb: the narrow band's half-width, in cells of the grid.
    double vdb_band = 3.0;
};

}  // namespace fortu
