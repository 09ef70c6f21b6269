// runtime/image_compare.cpp — see image_compare.hpp: the calls go through the image module,
// and the diff image is written atomically like every other output. A PNG is checked chunk by
// chunk (lengths, CRCs, IEND) before OpenImageIO sees it: libpng reports a damaged file by
// longjmp, which prints to stderr and leaks inside OpenImageIO, and its message is vaguer.
#include "runtime/image_compare.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/image_io.hpp"
#include "runtime/oiio_util.hpp"
#include "runtime/output_error.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <iterator>

namespace fortu {
namespace {

constexpr std::array<std::uint32_t, 256> kCrcTable = [] {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t n = 0; n < 256; ++n) {
        std::uint32_t c = n;
        for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        table[n] = c;
    }
    return table;
}();

std::uint32_t big_endian(const std::string& s, std::size_t at) {
    return std::uint32_t(std::uint8_t(s[at])) << 24 | std::uint32_t(std::uint8_t(s[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(s[at + 2])) << 8 | std::uint32_t(std::uint8_t(s[at + 3]));
}

/// Why the PNG file at `path` is damaged, or "" if its structure is sound (PNG spec §5).
std::string png_damage(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return fmt::format("cannot read '{}'", path);
    const std::string bytes(std::istreambuf_iterator<char>(in), {});
    if (bytes.compare(0, 8, "\x89PNG\r\n\x1a\n", 8) != 0) return fmt::format("'{}' is not a PNG file", path);
    for (std::size_t at = 8; at + 12 <= bytes.size();) {
        const std::uint32_t length = big_endian(bytes, at);
        std::string type = bytes.substr(at + 4, 4);
        for (char& c : type)
            if (!std::isalpha(static_cast<unsigned char>(c))) c = '?';  // a damaged name, printable
        if (length > bytes.size() - at - 12)
            return fmt::format("'{}' is cut short: its {} chunk at byte {} needs {} bytes, the file ends at {}", path,
                               type, at, std::size_t(length) + 12, bytes.size());
        std::uint32_t crc = 0xFFFFFFFFu;
        for (std::size_t i = at + 4; i < at + 8 + length; ++i) crc = kCrcTable[(crc ^ std::uint8_t(bytes[i])) & 0xFF] ^ (crc >> 8);
        if ((crc ^ 0xFFFFFFFFu) != big_endian(bytes, at + 8 + length))
            return fmt::format("'{}' is damaged: its {} chunk at byte {} fails its CRC", path, type, at);
        if (type == "IEND") return "";
        at += std::size_t(length) + 12;
    }
    return fmt::format("'{}' is cut short: it ends at byte {} before its IEND chunk", path, bytes.size());
}

bool is_png(const std::string& path) {
    return path.size() >= 4 && (path.compare(path.size() - 4, 4, ".png") == 0 || path.compare(path.size() - 4, 4, ".PNG") == 0);
}

std::string pixel_text(const std::vector<float>& values, const std::vector<std::string>& channels, bool picture) {
    std::string s;
    for (std::size_t c = 0; c < values.size(); ++c) {
        if (!s.empty()) s += ", ";
        if (picture) s += fmt::format("{}", static_cast<int>(std::lround(values[c] * 255.0f)));
        else s += fmt::format("{}={}", c < channels.size() ? channels[c] : fmt::format("c{}", c), values[c]);
    }
    return "(" + s + ")";
}

}  // namespace

ImageComparison compare_images(const std::string& expected_path, const std::string& actual_path,
                               double tolerance) {
    ImageComparison failed;
    for (const std::string& path : {expected_path, actual_path})
        if (is_png(path))
            if (failed.error = png_damage(path); !failed.error.empty()) return failed;
    const ImageModule* module = image_module(failed.error);
    if (!module) return failed;
    return module->compare(expected_path, actual_path, tolerance);
}

std::string write_diff_image(const std::string& expected_path, const std::string& actual_path,
                             int subimage, const std::string& diff_path) {
    std::string error;
    const ImageModule* module = image_module(error);
    if (!module) return error;
    try {
        write_atomically(diff_path, [&](const std::string& temp) {
            const std::string reason = module->write_difference(expected_path, actual_path, subimage, temp);
            if (!reason.empty()) throw OutputError(diff_path, oiio_reason(reason, temp, diff_path));
        });
    } catch (const OutputError& e) {
        return e.what();
    }
    return "";
}

OutputComparison compare_image_output(const ComparedOutput& compared) {
    const bool picture = compared.format.kind == OutputKind::Picture;
    const double tol = picture ? (compared.pixel_tolerance + 0.5) / 255.0 : compared.tolerance;
    const ImageComparison c = compare_images(compared.expected_path, compared.actual_path, tol);
    if (!c.error.empty()) return {fmt::format("cannot be compared: {}", c.error)};
    if (c.failing == 0) return {};
    const Grid& grid = compared.field.grid;
    const std::string where = grid.dims == 3 && !picture
        ? fmt::format("pixel ({}, {}) of slice {}", c.worst_x, c.worst_y, c.worst_subimage)
        : fmt::format("pixel ({}, {})", c.worst_x, c.worst_y);
    return {fmt::format(
                "{} of {} pixels differ by more than {} (max error {}); worst at {} (x {}, y {}): expected {}, got {}",
                format_count(c.failing), format_count(c.pixels),
                picture ? fmt::format("{} level(s)", compared.pixel_tolerance) : fmt::format("{}", compared.tolerance),
                picture ? fmt::format("{} levels", std::lround(c.max_error * 255.0)) : fmt::format("{}", static_cast<float>(c.max_error)),
                where, grid.x_at(c.worst_x), grid.y_at(c.worst_y), pixel_text(c.expected, c.channels, picture),
                pixel_text(c.actual, c.channels, picture)),
            c.worst_subimage};
}

std::string write_image_output_diff(const ComparedOutput& compared, const OutputComparison& comparison,
                                    const std::string& diff_path) {
    return write_diff_image(compared.expected_path, compared.actual_path, comparison.diff_subimage, diff_path);
}

}  // namespace fortu
