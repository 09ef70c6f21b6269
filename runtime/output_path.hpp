// runtime/output_path.hpp — what an output path says: its extension (the format) and whether
// it names a series of files through a printf-style number, e.g. `slice_%03d.png` (one
// picture per 3D slice) or `m_%d.png` (M-images M1..M4).
#pragma once

#include <string>
#include <string_view>

namespace fortu {

/// The extension of the file name in `path`, lower case, without the dot; "" if none.
std::string path_extension(std::string_view path);

/// True if `path` contains a number conversion: `%d`, or `%Wd` / `%0Wd` with a width W of
/// one or two digits.
bool is_file_series(std::string_view path);

/// `path` with every number conversion replaced by `number`, formatted as printf would
/// (`slice_%03d.png`, 7 → `slice_007.png`). Other text, other `%` signs included, is kept.
std::string file_series_name(std::string_view path, int number);

}  // namespace fortu
