// runtime/surface_picture.hpp — a shaded picture of a solid: per pixel the depth of the first
// surface along the view ray and its unit normal, coloured with a light at the viewer.
//
// Why here: the ray casting needs the model (interp/shaded_view.hpp); what a pixel looks
// like, and writing the file, are the pictures' concern, beside picture.hpp.
#pragma once

#include "runtime/output_options.hpp"
#include "runtime/picture.hpp"

#include <array>
#include <string>
#include <vector>

namespace fortu {

/// What the view ray of each pixel met, in image order (row 0 at the top).
struct SurfaceImage {
    enum class Hit : unsigned char { None, Surface, Cut };   ///< Cut: the solid meets the domain's face
    int width = 0;
    int height = 0;
    std::vector<Hit> hit;
    std::vector<float> depth;                    ///< 0 nearest to the viewer .. 1 farthest, where hit
    std::vector<std::array<float, 3>> normal;    ///< unit, in view coordinates (x right, y up, z to the viewer)
};

/// The colours: the papers' inside orange lit from the viewer (Lambert, a little ambient,
/// farther surfaces slightly darker), faces cut by the domain in cream, background white.
std::vector<Rgb8> shade_surface(const SurfaceImage& image);

/// Writes shade_surface() to `path` (a picture format), atomically. Throws OutputError.
void write_surface_picture(const SurfaceImage& image, const std::string& path, const OutputOptions& options = {});

}  // namespace fortu
