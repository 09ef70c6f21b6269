// cli/golden_compare.cpp — see golden_compare.hpp. The .npy reader accepts exactly what
// runtime/npy.cpp writes (v1.0, little-endian f8/f4, C order), which is what --update stores.
#include "cli/golden/golden_compare.hpp"

#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <vector>

namespace fortu {
namespace {

std::optional<std::string> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Two values agree: within tolerance, or the same non-finite value.
bool agree(double a, double b, double tolerance) {
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
    if (std::isinf(a) || std::isinf(b)) return a == b;
    return std::fabs(a - b) <= tolerance;
}

double distance(double a, double b) {
    if (agree(a, b, 0.0)) return 0.0;
    return std::isfinite(a) && std::isfinite(b) ? std::fabs(a - b) : INFINITY;
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

/// A text cut into the numbers in it and the text between them.
struct Tokens {
    std::vector<std::string> text;   ///< text[i] precedes numbers[i]; one more text than numbers
    std::vector<double> numbers;
    std::vector<int> lines;          ///< the line of each number
};

Tokens tokenize(const std::string& s) {
    Tokens t;
    t.text.emplace_back();
    int line = 1;
    for (std::size_t i = 0; i < s.size();) {
        const char c = s[i];
        const bool sign = (c == '-' || c == '+' || c == '.') && i + 1 < s.size() &&
                          (std::isdigit(static_cast<unsigned char>(s[i + 1])) ||
                           (s[i + 1] == '.' && i + 2 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 2]))));
        const bool starts = std::isdigit(static_cast<unsigned char>(c)) || sign;
        const bool after_word = i > 0 && (std::isalpha(static_cast<unsigned char>(s[i - 1])) || s[i - 1] == '_');
        if (starts && !after_word) {
            char* end = nullptr;
            const double v = std::strtod(s.c_str() + i, &end);
            const std::size_t used = static_cast<std::size_t>(end - (s.c_str() + i));
            if (used > 0) {
                t.numbers.push_back(v);
                t.lines.push_back(line);
                t.text.emplace_back();
                i += used;
                continue;
            }
        }
        if (c == '\n') ++line;
        t.text.back() += c;
        ++i;
    }
    return t;
}

std::string line_of(const std::string& s, int line) {
    std::size_t at = 0;
    for (int l = 1; l < line && at != std::string::npos; ++l) {
        at = s.find('\n', at);
        if (at != std::string::npos) ++at;
    }
    if (at == std::string::npos) return "";
    const std::size_t end = s.find('\n', at);
    std::string text = s.substr(at, end == std::string::npos ? std::string::npos : end - at);
    if (text.size() > 120) text = text.substr(0, 117) + "...";
    return text;
}

}  // namespace

FileComparison compare_npy(const std::string& expected_path, const Field& field, double tolerance) {
    const auto bytes = read_file(expected_path);
    if (!bytes) return {fmt::format("cannot read '{}'", expected_path)};
    std::vector<double> expected;
    if (std::string e = read_npy(*bytes, field.grid, expected); !e.empty())
        return {fmt::format("'{}' cannot be compared: {}", expected_path, e)};
    std::size_t failing = 0, worst = 0;
    double worst_distance = -1;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (agree(expected[i], field.values[i], tolerance)) continue;
        ++failing;
        const double d = distance(expected[i], field.values[i]);
        if (d > worst_distance) { worst_distance = d; worst = i; }
    }
    if (failing == 0) return {};
    const Grid& g = field.grid;
    const int col = static_cast<int>(worst % g.cols());
    const int row = static_cast<int>(worst / g.cols() % g.rows());
    const int slice = static_cast<int>(worst / (std::size_t(g.cols()) * g.rows()));
    const std::string where = g.dims == 3
        ? fmt::format("node (col {}, row {}, slice {}) = ({}, {}, {})", col, row, slice, g.x_at(col), g.y_at(row), g.z_at(slice))
        : fmt::format("node (col {}, row {}) = ({}, {})", col, row, g.x_at(col), g.y_at(row));
    return {fmt::format("{} of {} values differ by more than {}; worst at {}: expected {}, got {}",
                        format_count(failing), format_count(expected.size()), tolerance, where, expected[worst],
                        field.values[worst])};
}

std::optional<std::vector<double>> read_npy_values(const std::string& path, const Grid& grid) {
    const auto bytes = read_file(path);
    std::vector<double> values;
    if (!bytes || !read_npy(*bytes, grid, values).empty()) return std::nullopt;
    return values;
}

FileComparison compare_numeric_text(const std::string& expected_path, const std::string& actual_path,
                                    double tolerance) {
    const auto expected = read_file(expected_path);
    if (!expected) return {fmt::format("cannot read '{}'", expected_path)};
    const auto actual = read_file(actual_path);
    if (!actual) return {fmt::format("cannot read the new output '{}'", actual_path)};
    const Tokens a = tokenize(*expected), b = tokenize(*actual);
    // The text between numbers first: a different structure makes number matching meaningless.
    const std::size_t n = std::min(a.text.size(), b.text.size());
    std::size_t i = 0;
    while (i < n && a.text[i] == b.text[i]) ++i;
    if (i < n || a.text.size() != b.text.size()) {
        const int line = i == 0 ? 1 : i - 1 < a.lines.size() ? a.lines[i - 1] : b.lines[i - 1];
        return {fmt::format("the text differs on line {}:\n  expected: {}\n  actual:   {}", line,
                            line_of(*expected, line), line_of(*actual, line))};
    }
    std::size_t failing = 0, worst = 0;
    double worst_distance = -1;
    for (std::size_t i = 0; i < a.numbers.size(); ++i) {
        if (agree(a.numbers[i], b.numbers[i], tolerance)) continue;
        ++failing;
        const double d = distance(a.numbers[i], b.numbers[i]);
        if (d > worst_distance) { worst_distance = d; worst = i; }
    }
    if (failing == 0) return {};
    const int line = a.lines[worst];
    return {fmt::format("{} of {} numbers differ by more than {}; worst on line {}: expected {}, got {}\n"
                        "  expected: {}\n  actual:   {}",
                        format_count(failing), format_count(a.numbers.size()), tolerance, line, a.numbers[worst],
                        b.numbers[worst], line_of(*expected, line), line_of(*actual, b.lines[worst]))};
}

}  // namespace fortu
