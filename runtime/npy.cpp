// runtime/npy.cpp — .npy header and little-endian payload, streamed in blocks.
#include "runtime/npy.hpp"

#include "runtime/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

namespace fortu {
namespace {

constexpr std::size_t kBlock = 1 << 16;   // values per write

template <typename T>
void write_values(const Field& field, OutputFile& out) {
    using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
    std::vector<Bits> block;
    block.reserve(kBlock);
    for (std::size_t from = 0; from < field.values.size(); from += kBlock) {
        block.clear();
        const std::size_t to = std::min(field.values.size(), from + kBlock);
        for (std::size_t i = from; i < to; ++i) {
            Bits bits = std::bit_cast<Bits>(static_cast<T>(field.values[i]));
            if constexpr (std::endian::native == std::endian::big) {
                Bits swapped = 0;
                for (std::size_t b = 0; b < sizeof(Bits); ++b) swapped = swapped << 8 | (bits >> (8 * b) & 0xff);
                bits = swapped;
            }
            block.push_back(bits);
        }
        out.write(block.data(), block.size() * sizeof(Bits));
    }
}

}  // namespace

std::string npy_header(const Grid& grid, bool float32) {
    const std::string shape = grid.dims == 3
                                  ? fmt::format("({}, {}, {})", grid.slices(), grid.rows(), grid.cols())
                                  : fmt::format("({}, {})", grid.rows(), grid.cols());
    std::string dict = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': {}, }}",
                                   float32 ? "<f4" : "<f8", shape);
    // magic (6) + version (2) + length (2) + dict + padding + '\n' ≡ 0 (mod 64)
    const std::size_t unpadded = 10 + dict.size() + 1;
    dict.append((64 - unpadded % 64) % 64, ' ');
    dict += '\n';
    std::string header("\x93NUMPY\x01\x00", 8);
    header += static_cast<char>(dict.size() & 0xff);
    header += static_cast<char>(dict.size() >> 8 & 0xff);
    return header + dict;
}

void write_npy(const Field& field, const std::string& path, bool float32) {
    write_file_atomically(path, [&](OutputFile& out) {
        out.write(npy_header(field.grid, float32));
        if (float32) write_values<float>(field, out);
        else write_values<double>(field, out);
    });
}

}  // namespace fortu
