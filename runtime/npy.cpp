// runtime/npy.cpp — .npy header and little-endian payload, streamed in blocks; the reader
// accepts exactly what the writer writes, which is what `fortu golden --update` stores.
#include "runtime/npy.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/value_compare.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
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

/// The values of a fortu .npy file, or an error text.
std::string read_npy(const std::string& bytes, const Grid& grid, std::vector<double>& values) {
    if (bytes.size() < 10 || std::memcmp(bytes.data(), "\x93NUMPY", 6) != 0) return "it is not a .npy file";
    if (bytes[6] != 1) return fmt::format("it is a .npy file of version {}, fortu reads version 1", int(bytes[6]));
    const std::size_t header_len = std::uint8_t(bytes[8]) | std::size_t(std::uint8_t(bytes[9])) << 8;
    if (bytes.size() < 10 + header_len) return "its header is cut short";
    const std::string header = bytes.substr(10, header_len);
    const bool f8 = header.find("'descr': '<f8'") != std::string::npos;
    const bool f4 = header.find("'descr': '<f4'") != std::string::npos;
    if (!f8 && !f4) return "it does not hold little-endian float64 or float32 values";
    if (header.find("'fortran_order': False") == std::string::npos) return "it is not in C order";
    const std::string shape = grid.dims == 3 ? fmt::format("({}, {}, {})", grid.slices(), grid.rows(), grid.cols())
                                             : fmt::format("({}, {})", grid.rows(), grid.cols());
    const auto at = header.find("'shape': ");
    const auto end = at == std::string::npos ? at : header.find(')', at);
    const std::string found = end == std::string::npos ? "?" : header.substr(at + 9, end - at - 8);
    if (found != shape) return fmt::format("its shape is {}, the grid's {}", found, shape);
    const std::size_t width = f8 ? 8 : 4;
    const std::size_t n = grid.points();
    if (bytes.size() != 10 + header_len + n * width)
        return fmt::format("it holds {} bytes of values, the grid needs {}", bytes.size() - 10 - header_len, n * width);
    values.resize(n);
    const char* data = bytes.data() + 10 + header_len;
    for (std::size_t i = 0; i < n; ++i) {
        if (f8) {
            std::memcpy(&values[i], data + i * 8, 8);
        } else {
            float f;
            std::memcpy(&f, data + i * 4, 4);
            values[i] = f;
        }
    }
    return "";
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

void write_npy(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    const bool float32 = options.npy_float32;
    write_file_atomically(target.path, [&](OutputFile& out) {
        out.write(npy_header(field.grid, float32));
        if (float32) write_values<float>(field, out);
        else write_values<double>(field, out);
    });
    // A 3D array says nothing of where its nodes are: the sidecar does (README "Outputs").
    if (field.grid.dims == 3 && options.npy_sidecar) {
        const Grid& g = field.grid;
        write_file_atomically(target.path + ".json", [&](OutputFile& out) {
            out.write(fmt::format(
                "{{\n  \"shape\": [{}, {}, {}],\n  \"axes\": [\"z\", \"y\", \"x\"],\n"
                "  \"first\": {{\"x\": {:.17g}, \"y\": {:.17g}, \"z\": {:.17g}}},\n"
                "  \"step\": {{\"x\": {:.17g}, \"y\": {:.17g}, \"z\": {:.17g}}},\n"
                "  \"note\": \"value[k][j][i] is at x = first.x + i*step.x, y = first.y + j*step.y, "
                "z = first.z + k*step.z (y decreases down the rows: image order)\"\n}}\n",
                g.slices(), g.rows(), g.cols(), g.x_at(0), g.y_at(0), g.z_at(0), g.x.step(), -g.y.step(), g.z.step()));
        });
    }
}

std::optional<std::vector<double>> read_npy_values(const std::string& path, const Grid& grid) {
    const auto bytes = read_file_bytes(path);
    std::vector<double> values;
    if (!bytes || !read_npy(*bytes, grid, values).empty()) return std::nullopt;
    return values;
}

OutputComparison compare_npy(const ComparedOutput& compared) {
    const auto bytes = read_file_bytes(compared.expected_path);
    if (!bytes) return {fmt::format("cannot read '{}'", compared.expected_path)};
    std::vector<double> expected;
    if (std::string e = read_npy(*bytes, compared.field.grid, expected); !e.empty())
        return {fmt::format("'{}' cannot be compared: {}", compared.expected_path, e)};
    std::string difference = compare_field_values(expected, compared.field, compared.tolerance);
    return {std::move(difference), 0};
}

std::string write_npy_diff(const ComparedOutput& compared, const OutputComparison&, const std::string& diff_path) {
    const auto reference = read_npy_values(compared.expected_path, compared.field.grid);
    if (!reference) return "";
    Field diff = compared.field;
    for (std::size_t i = 0; i < diff.values.size(); ++i) diff.values[i] = std::fabs((*reference)[i] - compared.field.values[i]);
    OutputOptions picture;
    picture.draw_contour = false;
    try {
        write_field(diff, diff_path, picture);
    } catch (const OutputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace fortu
