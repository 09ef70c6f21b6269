// runtime/exr.cpp — float EXR through OpenImageIO, one part per 3D slice.
#include "runtime/exr.hpp"

#include "runtime/fv_model.hpp"
#include "runtime/output_error.hpp"

#include "runtime/image_io.hpp"
#include <fmt/format.h>

namespace fortu {
namespace {

std::string domain_text(const Grid& g) {
    std::string text = fmt::format("{:.17g}:{:.17g},{:.17g}:{:.17g}", g.x.min, g.x.max, g.y.min, g.y.max);
    if (g.dims == 3) text += fmt::format(",{:.17g}:{:.17g}", g.z.min, g.z.max);
    return text;
}

ImageLayer slice_layer(const Grid& g, int slice, const std::vector<float>& pixels) {
    ImageLayer layer;
    layer.cols = g.cols();
    layer.rows = g.rows();
    layer.channels = exr_channel_names(g);
    layer.is_float = true;
    layer.pixels = pixels.data();
    layer.text_attributes = {{"compression", "zip"}, {"Software", "fortu"}, {"fortu:domain", domain_text(g)}};
    if (g.dims == 3) {
        layer.text_attributes.emplace_back("oiio:subimagename", fmt::format("z{:04d}", slice));
        layer.float_attributes.emplace_back("fortu:z", static_cast<float>(g.z_at(slice)));
    }
    return layer;
}

// value, n1..n_k interleaved per pixel, in image order.
std::vector<float> slice_pixels(const Field& field, int slice) {
    const Grid& g = field.grid;
    const int k = g.dims == 3 ? 5 : 4;
    const std::size_t row_floats = static_cast<std::size_t>(g.cols()) * (k + 1);
    std::vector<float> pixels(row_floats * g.rows());
    for_each_fv_row(field, slice, [&](std::size_t r, const double* const* n) {
        float* p = pixels.data() + r * row_floats;
        for (int c = 0; c < g.cols(); ++c) {
            *p++ = static_cast<float>(field.values[g.index(c, static_cast<int>(r), slice)]);
            for (int j = 0; j < k; ++j) *p++ = static_cast<float>(n[j][c]);
        }
    });
    return pixels;
}

void write_parts(const Field& field, const std::string& path, int first, int count) {
    std::vector<std::vector<float>> pixels;
    std::vector<ImageLayer> layers;
    for (int s = first; s < first + count; ++s) pixels.push_back(slice_pixels(field, s));
    for (int i = 0; i < count; ++i) layers.push_back(slice_layer(field.grid, first + i, pixels[i]));
    write_image_file(path, layers);
}

}  // namespace

std::vector<std::string> exr_channel_names(const Grid& grid) {
    if (grid.dims == 3) return {"value", "n1", "n2", "n3", "n4", "n5"};
    return {"value", "n1", "n2", "n3", "n4"};
}

void write_exr(const Field& field, const OutputTarget& target, const OutputOptions&) {
    const Grid& g = field.grid;
    if (g.dims == 3 && target.series) {
        for (int s = 0; s < g.slices(); ++s) write_parts(field, target.file(s), s, 1);
        return;
    }
    write_parts(field, target.file(0), 0, g.slices());
}

}  // namespace fortu
