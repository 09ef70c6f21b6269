// runtime/vti.cpp — VTK XML ImageData writer (appended raw data, UInt64 block headers) and the
// reader of its own files for golden tests.
#include "runtime/vti.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/value_compare.hpp"
#include "runtime/volume_order.hpp"

#include <cstdint>
#include <cstring>
#include <fmt/format.h>

namespace fortu {
namespace {

int component_count(const Grid& g) { return fv_component_count(g); }

std::string header_text(const Grid& g, bool mimages, int first_slice = 0, int last_slice = -1) {
    const std::array<double, 3> o = volume_origin(g), s = volume_spacing(g);
    if (last_slice < 0) last_slice = g.slices() - 1;
    const std::string extent = fmt::format("0 {} 0 {} {} {}", g.cols() - 1, g.rows() - 1, first_slice, last_slice);
    std::string text = fmt::format(
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
        "  <ImageData WholeExtent=\"{0}\" Origin=\"{1:.17g} {2:.17g} {3:.17g}\" Spacing=\"{4:.17g} {5:.17g} {6:.17g}\">\n"
        "    <Piece Extent=\"{0}\">\n"
        "      <PointData Scalars=\"value\">\n"
        "        <DataArray type=\"Float64\" Name=\"value\" format=\"appended\" offset=\"0\"/>\n",
        extent, o[0], o[1], o[2], s[0], s[1], s[2]);
    if (mimages) {
        const std::uint64_t block = 8 + 8 * std::uint64_t(g.cols()) * g.rows() * (last_slice - first_slice + 1);
        for (int c = 0; c < component_count(g); ++c)
            text += fmt::format("        <DataArray type=\"Float64\" Name=\"n{}\" format=\"appended\" offset=\"{}\"/>\n",
                                c + 1, block * (c + 1));
    }
    text += "      </PointData>\n    </Piece>\n  </ImageData>\n  <AppendedData encoding=\"raw\">\n   _";
    return text;
}

constexpr std::string_view kTrailer = "\n  </AppendedData>\n</VTKFile>\n";

}  // namespace

std::string vti_header(const Grid& grid, bool mimages) { return header_text(grid, mimages); }
std::string vti_piece_header(const Grid& grid, int first_slice, int last_slice, bool mimages) {
    return header_text(grid, mimages, first_slice, last_slice);
}
std::string_view vti_trailer() { return kTrailer; }

void write_vti(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    const Grid& g = field.grid;
    const std::uint64_t bytes = 8 * std::uint64_t(g.points());
    write_file_atomically(target.path, [&](OutputFile& out) {
        out.write(header_text(g, options.mimages));
        out.write(&bytes, sizeof bytes);
        for_each_volume_row(field, [&](const double* row, int, int) { out.write(row, sizeof(double) * g.cols()); });
        if (options.mimages) {
            std::vector<double> component(g.cols());
            for (int c = 0; c < component_count(g); ++c) {
                out.write(&bytes, sizeof bytes);
                for (int k = 0; k < g.slices(); ++k)
                    for (int j = 0; j < g.rows(); ++j) {
                        for (int i = 0; i < g.cols(); ++i) component[i] = fv_node(field, i, g.rows() - 1 - j, k)[c];
                        out.write(component.data(), sizeof(double) * g.cols());
                    }
            }
        }
        out.write(kTrailer);
    });
}

std::optional<std::vector<double>> read_vti_values(const std::string& path, const Grid& grid) {
    const std::optional<std::string> bytes = read_file_bytes(path);
    if (!bytes) return std::nullopt;
    const std::size_t start = bytes->find("<AppendedData encoding=\"raw\">");
    if (start == std::string::npos) return std::nullopt;
    const std::size_t underscore = bytes->find('_', start);
    std::uint64_t size = 0;
    if (underscore == std::string::npos || underscore + 9 > bytes->size()) return std::nullopt;
    std::memcpy(&size, bytes->data() + underscore + 1, 8);
    if (size != 8 * grid.points() || underscore + 9 + size > bytes->size()) return std::nullopt;
    std::vector<double> values(grid.points());
    const char* data = bytes->data() + underscore + 9;
    // Back from volume order to image order.
    for (int k = 0; k < grid.slices(); ++k)
        for (int j = 0; j < grid.rows(); ++j)
            std::memcpy(values.data() + grid.index(0, grid.rows() - 1 - j, k),
                        data + 8 * (std::size_t(k) * grid.rows() + j) * grid.cols(), 8 * std::size_t(grid.cols()));
    return values;
}

OutputComparison compare_vti(const ComparedOutput& compared) {
    const std::optional<std::vector<double>> expected = read_vti_values(compared.expected_path, compared.field.grid);
    if (!expected)
        return {fmt::format("'{}' is not a .vti fortu wrote for this grid", compared.expected_path)};
    return {compare_field_values(*expected, compared.field, compared.tolerance), 0};
}

}  // namespace fortu
