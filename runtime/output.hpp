// runtime/output.hpp — writing a sampled Field to the file a user named: the format follows
// the extension (architecture.md "Outputs a user expects"); every file is written atomically.
// The per-format writers live in picture/exr/npy/csv/contour .hpp.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_options.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {

enum class OutputFormat {
    Png,    ///< picture: diverging colour map + zero contour (picture.hpp)
    Jpeg,   ///< picture, lossy
    Tiff,   ///< picture
    Bmp,    ///< picture
    Exr,    ///< float EXR, channels value, n1..n4 (3D: n1..n5), exr.hpp
    Npy,    ///< NumPy array of the raw values, npy.hpp
    Csv,    ///< x,y[,z],value per node, csv.hpp
    Svg,    ///< the zero contour as polylines, contour.hpp
};

/// The format for `path` by its extension (case-insensitive), or nullopt if fortu cannot
/// write it — so that the command line refuses it before doing any work.
std::optional<OutputFormat> output_format_for(const std::string& path);

/// The extensions output_format_for() accepts, lower case, without the dot, in the order of
/// OutputFormat (for usage messages).
std::vector<std::string> supported_output_extensions();

/// The format's usual name: "PNG", "JPEG", "TIFF", "BMP", "OpenEXR", "NumPy", "CSV", "SVG".
std::string_view output_format_name(OutputFormat format);

/// True for the 8-bit colour picture formats (Png, Jpeg, Tiff, Bmp).
bool is_picture_format(OutputFormat format);

/// Writes `field` to `path` in the format its extension names. Throws OutputError
/// (`cannot write 'PATH': REASON`) on any failure, leaving `path` untouched; an unknown
/// extension is an OutputError too. For a series path (`%d`) each file is atomic on its own.
void write_field(const Field& field, const std::string& path, const OutputOptions& options = {});

/// Why `path` cannot take the M-images, or nullopt if it can: it must end in `.exr`, or name
/// a PNG/TIFF/BMP series with a number conversion (`m_%d.png`; JPEG would corrupt the codes).
std::optional<std::string> mimages_path_problem(const std::string& path);

/// Writes the FV model's M-images of `field` (fv-method.md §1): to `.exr`, the same float EXR
/// as write_field() (value and n1..n4 / n1..n5, unquantised); to a series path, n+2 picture
/// files M1..M4 (3D: M1..M5 of the chosen slice), the number conversion replaced by 1..n+2,
/// each palette-encoded: 8-bit grey (Palette::Grey8) or 24-bit RGB (Palette::Rgb24) as
/// options.mimage_palette says. Throws OutputError.
void write_mimages(const Field& field, const std::string& path, const OutputOptions& options = {});

}  // namespace fortu
