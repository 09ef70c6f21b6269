// runtime/output.cpp — the dispatch to the writer of output_formats.hpp's row, and the
// M-images (fv-method.md §1: n+2 palette images or one float EXR).
#include "runtime/output.hpp"

#include "runtime/fv_model.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_path.hpp"
#include "runtime/palette.hpp"
#include "runtime/picture.hpp"

#include <fmt/format.h>

#include <cstdint>

namespace fortu {
namespace {

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

void write_field(const Field& field, const std::string& path, const OutputOptions& options) {
    write_field(field, resolve_output(path), options);
}

void write_field(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    if (!target.format->write)
        throw OutputError(target.path, fmt::format("{} holds a mesh, made from the model by 'fortu run', not grid values",
                                                   target.format->name));
    check_field(field, target.path);
    target.format->write(field, target, options);
}

void write_mesh(const Mesh& mesh, const OutputTarget& target, const OutputOptions& options) {
    if (!target.format->write_mesh) throw OutputError(target.path, fmt::format("{} does not hold a mesh", target.format->name));
    if (target.series) throw OutputError(target.path, "a mesh is one file: take the %d out of the name");
    target.format->write_mesh(mesh, target.path, options);
}

std::optional<std::string> mimages_path_problem(const std::string& path) {
    const OutputFormat* format = output_format_for(path);
    if (format && (format->kind == OutputKind::MImages || format->takes_mimages)) return std::nullopt;
    if (format && format->kind == OutputKind::Picture && format->lossy)
        return fmt::format("{} is lossy and would corrupt the M-image codes; use .png", format->name);
    if (!format || format->kind != OutputKind::Picture) {
        std::vector<std::string> files;   // the table's rows that hold the components
        for (const OutputFormat& f : output_formats())
            if (f.kind == OutputKind::MImages || f.takes_mimages) files.push_back(fmt::format(".{}", f.extension()));
        std::string list = files.front();
        for (std::size_t i = 1; i < files.size(); ++i) list += (i + 1 == files.size() ? " or " : ", ") + files[i];
        const std::string need = fmt::format("M-images need a {} file or a picture series such as 'm_%d.png'", list);
        if (format && format->kind == OutputKind::Volume) return fmt::format("{} holds the value alone{}; {}",
            format->name, format->holds.empty() ? "" : fmt::format(" ({})", format->holds), need);
        return need;
    }
    if (!is_file_series(path))
        return "M-images are n+2 pictures: put %d in the name (e.g. 'm_%d.png') or use .exr";
    return std::nullopt;
}

void write_mimages(const Field& field, const std::string& path, const OutputOptions& options) {
    if (const auto problem = mimages_path_problem(path)) throw OutputError(path, *problem);
    check_field(field, path);
    const OutputTarget target = resolve_output(path);
    if (target.format->kind == OutputKind::MImages) {
        target.format->write(field, target, options);
        return;
    }
    if (target.format->takes_mimages) {
        OutputOptions with_components = options;
        with_components.mimages = true;
        target.format->write(field, target, with_components);
        return;
    }
    const Grid& g = field.grid;
    const int slice = picture_slice(g, options.slice);
    if (slice < 0)
        throw OutputError(path, fmt::format("slice {} is out of range 0..{}", options.slice, g.slices() - 1));
    const int channels = options.mimage_palette == Palette::Grey8 ? 1 : 3;
    const auto images = mimage_pixels(field, slice, options.mimage_palette);
    for (std::size_t k = 0; k < images.size(); ++k)
        write_image_8bit(target.file(static_cast<int>(k) + 1), g.cols(), g.rows(), channels,
                         images[k], options);
}

}  // namespace fortu
