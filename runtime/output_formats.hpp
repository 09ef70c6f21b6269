// runtime/output_formats.hpp — the one list of output formats fortu writes: per format its
// extensions, kind, writer and the comparator `fortu golden` uses. The usage text, the
// command-line checks and the golden runner read this list, so a new format is one writer
// file and one row in output_formats.cpp.
#pragma once

#include "runtime/field.hpp"
#include "runtime/mesh.hpp"
#include "runtime/output_options.hpp"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {

/// What a file of the format shows of a field; decides which flags accept it.
enum class OutputKind {
    Picture,   ///< 8-bit colour picture of one slice (picture.hpp); --mimages as a series
    Field,     ///< the raw values at every node (npy, csv)
    Contour,   ///< the zero contour as lines (--contour)
    MImages,   ///< the value and the FV model's components n1.. in one file (--mimages)
    Mesh,      ///< the zero surface as triangles (write_mesh; mesh_io.hpp)
    Volume,    ///< a 3D volume for viewers with its origin and spacing (vti, nrrd, vdb)
};

struct OutputFormat;

/// Where a writer writes: the path resolved once, its format and whether it names a series
/// of files through a number conversion (`slice_%03d.png`, output_path.hpp).
struct OutputTarget {
    std::string path;
    const OutputFormat* format = nullptr;
    bool series = false;

    /// The file for one member of a series (`number` replaces the conversion); `path` when
    /// the target is not a series.
    std::string file(int number) const;
};

/// What a comparator compares: a golden test's reference file with the new output written
/// from `field` by the same format's writer.
struct ComparedOutput {
    const OutputFormat& format;
    std::string expected_path;
    std::string actual_path;
    const Field& field;
    double tolerance = 1e-9;   ///< absolute, for values (npy, csv, svg, exr)
    int pixel_tolerance = 0;   ///< 8-bit levels, for pictures
};

/// A comparator's verdict: `difference` is empty when the files agree, else a paragraph
/// saying what differed. `diff_subimage` >= 0 when a picture of the difference can be drawn
/// (the subimage, i.e. 3D slice, to draw; 0 for formats without subimages).
struct OutputComparison {
    std::string difference;
    int diff_subimage = -1;
    bool ok() const { return difference.empty(); }
};

using OutputWriter = void (*)(const Field& field, const OutputTarget& target, const OutputOptions& options);
/// Mesh formats: writes the mesh the mesher made (interp/mesher.hpp) to `path`.
using MeshWriter = void (*)(const Mesh& mesh, const std::string& path, const OutputOptions& options);
using OutputComparator = OutputComparison (*)(const ComparedOutput& compared);
/// Draws the difference of a failed comparison to `diff_path`; "" or an error text.
using DiffWriter = std::string (*)(const ComparedOutput& compared, const OutputComparison& comparison,
                                   const std::string& diff_path);

/// One row of the list.
struct OutputFormat {
    std::string_view name{};                     ///< "PNG", "OpenEXR", ...
    std::vector<std::string_view> extensions{};  ///< lower case, no dot; the first is the usual one
    OutputKind kind = OutputKind::Field;
    std::string_view holds{};                    ///< for the usage text: what the file holds
    bool lossy = false;                          ///< would corrupt M-image codes
    bool takes_mimages = false;                  ///< a Volume that also holds the M-image components (--mimages)
    OutputWriter write = nullptr;
    OutputComparator compare = nullptr;          ///< nullptr: golden tests do not offer it
    DiffWriter write_diff = nullptr;             ///< nullptr: no picture of a difference
    std::string_view diff_name{};                ///< NAME.<diff_name> beside a failing golden test
    MeshWriter write_mesh = nullptr;             ///< OutputKind::Mesh rows: the writer (`write` is unused)
    bool text = false;                           ///< plain text: `-o -` may write it to a terminal

    /// The usual extension, which also names the format in `// golden-output` directives.
    std::string_view extension() const { return extensions.front(); }
};

/// Every format, in the order the usage text lists them.
std::span<const OutputFormat> output_formats();

/// The format for `path` by its extension (case-insensitive), or nullptr if fortu cannot
/// write it — so that the command line refuses it before doing any work.
const OutputFormat* output_format_for(std::string_view path);

/// `path` resolved once for the writers. Throws OutputError (`unknown output format '.xyz'
/// (known: png, jpg, ...)`) for an extension no row has.
OutputTarget resolve_output(const std::string& path);

/// Every extension of every row, lower case, without the dot, in table order.
std::vector<std::string> supported_output_extensions();

/// The usual extensions with their dots, `separator` between them: ".png .jpg ... .svg".
std::string output_extensions_text(std::string_view separator = " ");

/// The `-o FILE` paragraph of the usage text, one line per kind (`picture: .png .jpg ...`),
/// each line after the first indented by `indent` spaces; ends without a newline.
std::string output_formats_usage(int indent);

/// The formats a golden test can compare (rows with a comparator), by usual extension:
/// png, exr, npy, csv, svg.
std::vector<std::string> golden_output_kinds();

/// The format a golden test's `kind` names (its usual extension), or nullptr.
const OutputFormat* golden_output_format(std::string_view kind);

}  // namespace fortu
