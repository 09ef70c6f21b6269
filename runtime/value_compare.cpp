// runtime/value_compare.cpp — see value_compare.hpp.
#include "runtime/value_compare.hpp"

#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iterator>

namespace fortu {

bool values_agree(double expected, double actual, double tolerance) {
    if (std::isnan(expected) || std::isnan(actual)) return std::isnan(expected) && std::isnan(actual);
    if (std::isinf(expected) || std::isinf(actual)) return expected == actual;
    return std::fabs(expected - actual) <= tolerance;
}

double value_distance(double expected, double actual) {
    if (values_agree(expected, actual, 0.0)) return 0.0;
    return std::isfinite(expected) && std::isfinite(actual) ? std::fabs(expected - actual) : INFINITY;
}

std::string compare_field_values(std::span<const double> expected, const Field& field, double tolerance) {
    std::size_t failing = 0, worst = 0;
    double worst_distance = -1;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        if (values_agree(expected[i], field.values[i], tolerance)) continue;
        ++failing;
        const double d = value_distance(expected[i], field.values[i]);
        if (d > worst_distance) { worst_distance = d; worst = i; }
    }
    if (failing == 0) return "";
    const Grid& g = field.grid;
    const int col = static_cast<int>(worst % g.cols());
    const int row = static_cast<int>(worst / g.cols() % g.rows());
    const int slice = static_cast<int>(worst / (std::size_t(g.cols()) * g.rows()));
    const std::string where = g.dims == 3
        ? fmt::format("node (col {}, row {}, slice {}) = ({}, {}, {})", col, row, slice, g.x_at(col), g.y_at(row), g.z_at(slice))
        : fmt::format("node (col {}, row {}) = ({}, {})", col, row, g.x_at(col), g.y_at(row));
    return fmt::format("{} of {} values differ by more than {}; worst at {}: expected {}, got {}",
                       format_count(failing), format_count(expected.size()), tolerance, where, expected[worst],
                       field.values[worst]);
}

std::optional<std::string> read_file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace fortu
