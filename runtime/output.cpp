// runtime/output.cpp — the extension table, the dispatch to the per-format writers, and the
// M-images (fv-method.md §1: n+2 palette images or one float EXR).
#include "runtime/output.hpp"

#include "runtime/contour.hpp"
#include "runtime/csv.hpp"
#include "runtime/exr.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/npy.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_path.hpp"
#include "runtime/palette.hpp"
#include "runtime/picture.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>

namespace fortu {
namespace {

struct ExtensionEntry {
    std::string_view extension;
    OutputFormat format;
};

constexpr std::array kExtensions{
    ExtensionEntry{"png", OutputFormat::Png},  ExtensionEntry{"jpg", OutputFormat::Jpeg},
    ExtensionEntry{"jpeg", OutputFormat::Jpeg}, ExtensionEntry{"tif", OutputFormat::Tiff},
    ExtensionEntry{"tiff", OutputFormat::Tiff}, ExtensionEntry{"bmp", OutputFormat::Bmp},
    ExtensionEntry{"exr", OutputFormat::Exr},  ExtensionEntry{"npy", OutputFormat::Npy},
    ExtensionEntry{"csv", OutputFormat::Csv},  ExtensionEntry{"svg", OutputFormat::Svg},
};

void check_field(const Field& field, const std::string& path) {
    const Grid& g = field.grid;
    if (g.cols() < 1 || g.rows() < 1 || g.slices() < 1)
        throw OutputError(path, "the grid has no points");
    if (field.values.size() != g.points())
        throw OutputError(path, fmt::format("the field has {} values for a grid of {} points",
                                            field.values.size(), g.points()));
}

// The M-images M1..M_{n+2} of one slice as 8-bit pixels, one vector per image: grey (1 byte
// per pixel) or the 24-bit code packed into R, G, B (fv-method.md §1.1 item 5).
std::vector<std::vector<std::uint8_t>> mimage_pixels(const Field& field, int slice, Palette palette) {
    const Grid& g = field.grid;
    const int components = g.dims == 3 ? 5 : 4;
    const std::size_t channels = palette == Palette::Grey8 ? 1 : 3;
    const std::size_t row_bytes = static_cast<std::size_t>(g.cols()) * channels;
    std::vector<std::vector<std::uint8_t>> images(components, std::vector<std::uint8_t>(row_bytes * g.rows()));
    for_each_fv_row(field, slice, [&](std::size_t r, const double* const* n) {
        for (int k = 0; k < components; ++k) {
            std::uint8_t* pixel = images[k].data() + r * row_bytes;
            for (int c = 0; c < g.cols(); ++c) {
                const std::uint32_t m = palette_encode(n[k][c], palette);
                if (palette == Palette::Grey8) {
                    *pixel++ = static_cast<std::uint8_t>(m);
                } else {
                    const auto rgb = rgb24_pack(m);
                    pixel = std::copy(rgb.begin(), rgb.end(), pixel);
                }
            }
        }
    });
    return images;
}

}  // namespace

std::optional<OutputFormat> output_format_for(const std::string& path) {
    const std::string ext = path_extension(path);
    for (const auto& entry : kExtensions)
        if (entry.extension == ext) return entry.format;
    return std::nullopt;
}

std::vector<std::string> supported_output_extensions() {
    std::vector<std::string> out;
    for (const auto& entry : kExtensions) out.emplace_back(entry.extension);
    return out;
}

std::string_view output_format_name(OutputFormat format) {
    switch (format) {
        case OutputFormat::Png: return "PNG";
        case OutputFormat::Jpeg: return "JPEG";
        case OutputFormat::Tiff: return "TIFF";
        case OutputFormat::Bmp: return "BMP";
        case OutputFormat::Exr: return "OpenEXR";
        case OutputFormat::Npy: return "NumPy";
        case OutputFormat::Csv: return "CSV";
        case OutputFormat::Svg: return "SVG";
    }
    return "?";
}

bool is_picture_format(OutputFormat format) {
    return format == OutputFormat::Png || format == OutputFormat::Jpeg || format == OutputFormat::Tiff ||
           format == OutputFormat::Bmp;
}

void write_field(const Field& field, const std::string& path, const OutputOptions& options) {
    const auto format = output_format_for(path);
    if (!format) {
        throw OutputError(path, fmt::format("unknown output format '.{}' (known: {})", path_extension(path),
                                            fmt::join(supported_output_extensions(), ", ")));
    }
    check_field(field, path);
    switch (*format) {
        case OutputFormat::Png:
        case OutputFormat::Jpeg:
        case OutputFormat::Tiff:
        case OutputFormat::Bmp: write_picture(field, path, options); return;
        case OutputFormat::Exr: write_exr(field, path); return;
        case OutputFormat::Npy: write_npy(field, path, options.npy_float32); return;
        case OutputFormat::Csv: write_csv(field, path); return;
        case OutputFormat::Svg: write_contour_svg(field, path, options); return;
    }
}

std::optional<std::string> mimages_path_problem(const std::string& path) {
    const auto format = output_format_for(path);
    if (format == OutputFormat::Exr) return std::nullopt;
    if (format == OutputFormat::Jpeg) return "JPEG is lossy and would corrupt the M-image codes; use .png";
    if (!format || !is_picture_format(*format))
        return "M-images need a .exr file or a picture series such as 'm_%d.png'";
    if (!is_file_series(path))
        return "M-images are n+2 pictures: put %d in the name (e.g. 'm_%d.png') or use .exr";
    return std::nullopt;
}

void write_mimages(const Field& field, const std::string& path, const OutputOptions& options) {
    if (const auto problem = mimages_path_problem(path)) throw OutputError(path, *problem);
    check_field(field, path);
    if (output_format_for(path) == OutputFormat::Exr) {
        write_exr(field, path);
        return;
    }
    const Grid& g = field.grid;
    const int slice = picture_slice(g, options.slice);
    if (slice < 0)
        throw OutputError(path, fmt::format("slice {} is out of range 0..{}", options.slice, g.slices() - 1));
    const int channels = options.mimage_palette == Palette::Grey8 ? 1 : 3;
    const auto images = mimage_pixels(field, slice, options.mimage_palette);
    for (std::size_t k = 0; k < images.size(); ++k)
        write_image_8bit(file_series_name(path, static_cast<int>(k) + 1), g.cols(), g.rows(), channels,
                         images[k], options);
}

}  // namespace fortu
