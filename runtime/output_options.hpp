// runtime/output_options.hpp — the choices a user can make about output files, shared by all
// writers (output.hpp dispatches on the file extension).
#pragma once

#include "runtime/palette.hpp"

#include <array>
#include <vector>

namespace fortu {

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
    /// Meshes: ASCII STL instead of binary.
    bool ascii = false;
    /// Volume formats that can hold them (.vti): add the FV model's components n1.. as
    /// point data (`--mimages m.vti`).
    bool mimages = false;
    /// .vdb: the narrow band's half-width, in cells of the grid.
    double vdb_band = 3.0;
};

}  // namespace fortu
