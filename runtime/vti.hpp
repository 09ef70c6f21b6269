// runtime/vti.hpp — a field as VTK XML ImageData (.vti), which ParaView and VisIt open:
// origin, spacing, the value as point data "value" (Float64) and, for --mimages m.vti, the
// FV model's components "n1".."n5" (fv_model.hpp), in appended raw binary.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"

#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// Writes the .vti (options.mimages: with the n components). Throws OutputError.
void write_vti(const Field& field, const OutputTarget& target, const OutputOptions& options);

/// The bytes before the value array of a .vti write_vti() writes for `grid` (the header,
/// then the array's UInt64 length follows), and those after its last array: a bricked run
/// (brick_output.hpp) writes the same file at offsets. With `mimages`, the arrays n1..
/// (fv_component_count()) follow the value's, each after its own length.
std::string vti_header(const Grid& grid, bool mimages = false);
std::string_view vti_trailer();
/// The header of a piece of that file holding slices first..last (the .pvti's pieces):
/// its extent is the piece's, origin and spacing the whole grid's.
std::string vti_piece_header(const Grid& grid, int first_slice, int last_slice, bool mimages = false);

/// The "value" array of a .vti that write_vti() wrote for `grid`, in fortu's image order, or
/// nullopt when the file is not one (the golden comparator reads it back).
std::optional<std::vector<double>> read_vti_values(const std::string& path, const Grid& grid);

/// Compares a reference .vti with the field, value by value.
OutputComparison compare_vti(const ComparedOutput& compared);

}  // namespace fortu
