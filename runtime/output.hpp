// runtime/output.hpp — writing a sampled Field to the file a user named: the format follows
// the extension (architecture.md "Outputs a user expects"); every file is written atomically.
// The formats and their writers are listed in output_formats.hpp.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_options.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {

/// Writes `field` to `path` in the format its extension names. Throws OutputError
/// (`cannot write 'PATH': REASON`) on any failure, leaving `path` untouched; an unknown
/// extension is an OutputError too. For a series path (`%d`) each file is atomic on its own.
void write_field(const Field& field, const std::string& path, const OutputOptions& options = {});

/// The same for a path already resolved (resolve_output()).
void write_field(const Field& field, const OutputTarget& target, const OutputOptions& options = {});

/// Writes `mesh` (interp/mesher.hpp) to a mesh format's file (OutputKind::Mesh); throws
/// OutputError, also for a target of another kind.
void write_mesh(const Mesh& mesh, const OutputTarget& target, const OutputOptions& options = {});

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
