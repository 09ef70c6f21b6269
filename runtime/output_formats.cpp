// runtime/output_formats.cpp — the table of output formats (see output_formats.hpp) and what
// is generated from it: extension lookup, the usage text, the golden kinds.
#include "runtime/output_formats.hpp"

#include "runtime/brick_output.hpp"
#include "runtime/contour.hpp"
#include "runtime/csv.hpp"
#include "runtime/exr.hpp"
#include "runtime/image_compare.hpp"
#include "runtime/mesh_compare.hpp"
#include "runtime/mesh_io.hpp"
#include "runtime/npy.hpp"
#include "runtime/nrrd.hpp"
#include "runtime/vdb.hpp"
#include "runtime/vti.hpp"
#include "runtime/numeric_text_compare.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_path.hpp"
#include "runtime/picture.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace fortu {
namespace {

// The one list.
const std::vector<OutputFormat> kFormats{
    {.name = "PNG", .extensions = {"png"}, .kind = OutputKind::Picture, .write = write_picture,
     .compare = compare_image_output, .write_diff = write_image_output_diff, .diff_name = "diff.png"},
    {.name = "JPEG", .extensions = {"jpg", "jpeg"}, .kind = OutputKind::Picture, .lossy = true, .write = write_picture},
    {.name = "TIFF", .extensions = {"tif", "tiff"}, .kind = OutputKind::Picture, .write = write_picture},
    {.name = "BMP", .extensions = {"bmp"}, .kind = OutputKind::Picture, .write = write_picture},
    {.name = "OpenEXR", .extensions = {"exr"}, .kind = OutputKind::MImages, .holds = "value + n1..n4 channels",
     .write = write_exr, .compare = compare_image_output, .write_diff = write_image_output_diff, .diff_name = "diff.exr"},
    {.name = "NumPy", .extensions = {"npy"}, .kind = OutputKind::Field, .write = write_npy, .compare = compare_npy,
     .write_diff = write_npy_diff, .diff_name = "values-diff.png"},
    {.name = "CSV", .extensions = {"csv"}, .kind = OutputKind::Field, .holds = "x,y[,z],value lines", .write = write_csv,
     .compare = compare_numeric_text, .text = true},
    {.name = "SVG", .extensions = {"svg"}, .kind = OutputKind::Contour, .write = write_contour_svg,
     .compare = compare_numeric_text, .text = true},
    {.name = "STL", .extensions = {"stl"}, .kind = OutputKind::Mesh, .holds = "binary; ASCII with --ascii",
     .compare = compare_mesh_output, .write_mesh = write_stl},
    {.name = "Wavefront OBJ", .extensions = {"obj"}, .kind = OutputKind::Mesh, .holds = "with normals",
     .compare = compare_mesh_output, .write_mesh = write_obj, .text = true},
    {.name = "PLY", .extensions = {"ply"}, .kind = OutputKind::Mesh, .holds = "binary, float64",
     .compare = compare_mesh_output, .write_mesh = write_ply},
    {.name = "VTK ImageData", .extensions = {"vti"}, .kind = OutputKind::Volume, .holds = "ParaView; value [+ n1..n5]",
     .takes_mimages = true, .write = write_vti, .compare = compare_vti},
    {.name = "NRRD", .extensions = {"nrrd"}, .kind = OutputKind::Volume, .write = write_nrrd, .compare = compare_nrrd},
    {.name = "OpenVDB", .extensions = {"vdb"}, .kind = OutputKind::Volume, .holds = "narrow band, --band", .write = write_vdb},
    {.name = "VTK parallel ImageData", .extensions = {"pvti"}, .kind = OutputKind::Volume,
     .holds = ".vti pieces, one per MPI rank", .takes_mimages = true, .write = write_field_as_brick},
    {.name = "VTKHDF ImageData", .extensions = {"hdf", "vtkhdf"}, .kind = OutputKind::Volume,
     .holds = "VTKHDF, ParaView 5.10+", .takes_mimages = true, .write = write_field_as_brick},
};

/// How the usage text names a kind.
std::string_view kind_words(OutputKind kind) {
    switch (kind) {
        case OutputKind::Picture: return "picture";
        case OutputKind::Field: return "values";
        case OutputKind::Contour: return "zero contour";
        case OutputKind::MImages: return "M-images";
        case OutputKind::Mesh: return "mesh";
        case OutputKind::Volume: return "volume";
    }
    return "?";
}

}  // namespace

std::string OutputTarget::file(int number) const { return series ? file_series_name(path, number) : path; }

std::span<const OutputFormat> output_formats() { return kFormats; }

const OutputFormat* output_format_for(std::string_view path) {
    const std::string ext = path_extension(path);
    for (const OutputFormat& format : kFormats)
        if (std::find(format.extensions.begin(), format.extensions.end(), ext) != format.extensions.end())
            return &format;
    return nullptr;
}

OutputTarget resolve_output(const std::string& path) {
    const OutputFormat* format = output_format_for(path);
    if (!format)
        throw OutputError(path, fmt::format("unknown output format '.{}' (known: {})", path_extension(path),
                                            fmt::join(supported_output_extensions(), ", ")));
    return {path, format, is_file_series(path)};
}

std::vector<std::string> supported_output_extensions() {
    std::vector<std::string> out;
    for (const OutputFormat& format : kFormats)
        for (std::string_view ext : format.extensions) out.emplace_back(ext);
    return out;
}

std::string output_extensions_text(std::string_view separator) {
    std::string out;
    for (const OutputFormat& format : kFormats)
        out += fmt::format("{}.{}", out.empty() ? "" : separator, format.extension());
    return out;
}

std::string output_formats_usage(int indent) {
    std::string out;
    for (std::size_t i = 0; i < kFormats.size();) {
        const OutputKind kind = kFormats[i].kind;
        std::string line = fmt::format("{}:", kind_words(kind));
        for (; i < kFormats.size() && kFormats[i].kind == kind; ++i) {
            line += fmt::format(" .{}", kFormats[i].extension());
            if (!kFormats[i].holds.empty()) line += fmt::format(" ({})", kFormats[i].holds);
        }
        if (!out.empty()) out.append("\n").append(static_cast<std::size_t>(indent), ' ');
        out += line;
    }
    return out;
}

std::vector<std::string> golden_output_kinds() {
    std::vector<std::string> out;
    for (const OutputFormat& format : kFormats)
        if (format.compare) out.emplace_back(format.extension());
    return out;
}

const OutputFormat* golden_output_format(std::string_view kind) {
    for (const OutputFormat& format : kFormats)
        if (format.compare && format.extension() == kind) return &format;
    return nullptr;
}

}  // namespace fortu
