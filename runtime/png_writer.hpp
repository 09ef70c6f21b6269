// runtime/png_writer.hpp — 8-bit PNG encoding with Debian's libpng, in the core.
//
// Why not OpenImageIO, which writes every other picture format: loading its module maps ~260
// libraries, about a second before the first pixel, against milliseconds to evaluate a small
// picture. PNG is the format people write most, and libpng alone loads in microseconds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fortu {

/// Encodes cols x rows 8-bit pixels (`channels` 1 grey, 2 grey+alpha, 3 RGB or 4 RGBA, row 0
/// at the top) as a PNG file's bytes, replacing `bytes`. An RGB picture of at most 256 colours
/// is written with a palette (readers expand it to the same pixels). Deterministic: the same
/// pixels give the same bytes. Returns "" or the reason it cannot.
std::string encode_png(int cols, int rows, int channels, const std::uint8_t* pixels,
                       std::vector<unsigned char>& bytes);

}  // namespace fortu
