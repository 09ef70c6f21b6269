// runtime/surface_picture.cpp — Lambert shading of a SurfaceImage.
#include "runtime/surface_picture.hpp"

#include <algorithm>
#include <cmath>

namespace fortu {

std::vector<Rgb8> shade_surface(const SurfaceImage& image) {
    // Light from the upper left of the viewer, so that faces facing the viewer are not flat.
    const float lx = -0.35f, ly = 0.45f, lz = 0.82f;
    const float norm = std::sqrt(lx * lx + ly * ly + lz * lz);
    std::vector<Rgb8> pixels(image.hit.size(), Rgb8{255, 255, 255});
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        if (image.hit[i] == SurfaceImage::Hit::None) continue;
        const auto& n = image.normal[i];
        float lambert = (n[0] * lx + n[1] * ly + n[2] * lz) / norm;
        if (!std::isfinite(lambert)) lambert = 0.5f;
        lambert = std::clamp(lambert, 0.0f, 1.0f);
        const float fade = 1.0f - 0.25f * std::clamp(image.depth[i], 0.0f, 1.0f);
        const float light = (0.18f + 0.82f * lambert) * fade;
        const Rgb8 base = image.hit[i] == SurfaceImage::Hit::Cut ? kInsideNear : kInsideFar;
        auto channel = [&](std::uint8_t c) { return static_cast<std::uint8_t>(std::lround(std::clamp(c * light, 0.0f, 255.0f))); };
        pixels[i] = {channel(base.r), channel(base.g), channel(base.b)};
    }
    return pixels;
}

void write_surface_picture(const SurfaceImage& image, const std::string& path, const OutputOptions& options) {
    const std::vector<Rgb8> pixels = shade_surface(image);
    std::vector<std::uint8_t> bytes;
    bytes.reserve(pixels.size() * 3);
    for (const Rgb8& p : pixels) bytes.insert(bytes.end(), {p.r, p.g, p.b});
    write_image_8bit(path, image.width, image.height, 3, bytes, options);
}

}  // namespace fortu
