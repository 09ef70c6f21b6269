// runtime/nrrd.cpp — NRRD0004 with an attached header, raw encoding.
#include "runtime/nrrd.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/value_compare.hpp"
#include "runtime/volume_order.hpp"

#include <cstring>
#include <fmt/format.h>

namespace fortu {

std::string nrrd_header(const Grid& g) {
    const std::array<double, 3> o = volume_origin(g), s = volume_spacing(g);
    if (g.dims == 3)
        return fmt::format("NRRD0004\n# written by fortu: the model's value at every grid node\ntype: double\n"
                           "dimension: 3\nsizes: {} {} {}\nspace dimension: 3\n"
                           "space directions: ({:.17g},0,0) (0,{:.17g},0) (0,0,{:.17g})\n"
                           "space origin: ({:.17g},{:.17g},{:.17g})\nendian: little\nencoding: raw\n\n",
                           g.cols(), g.rows(), g.slices(), s[0], s[1], s[2], o[0], o[1], o[2]);
    return fmt::format("NRRD0004\n# written by fortu: the model's value at every grid node\ntype: double\n"
                       "dimension: 2\nsizes: {} {}\nspace dimension: 2\n"
                       "space directions: ({:.17g},0) (0,{:.17g})\nspace origin: ({:.17g},{:.17g})\n"
                       "endian: little\nencoding: raw\n\n",
                       g.cols(), g.rows(), s[0], s[1], o[0], o[1]);
}

void write_nrrd(const Field& field, const OutputTarget& target, const OutputOptions&) {
    const Grid& g = field.grid;
    write_file_atomically(target.path, [&](OutputFile& out) {
        out.write(nrrd_header(g));
        for_each_volume_row(field, [&](const double* row, int, int) { out.write(row, sizeof(double) * g.cols()); });
    });
}

OutputComparison compare_nrrd(const ComparedOutput& compared) {
    const Grid& g = compared.field.grid;
    const std::optional<std::string> bytes = read_file_bytes(compared.expected_path);
    const std::string header = nrrd_header(g);
    if (!bytes || bytes->compare(0, header.size(), header) != 0 || bytes->size() != header.size() + 8 * g.points())
        return {fmt::format("'{}' is not a .nrrd fortu wrote for this grid", compared.expected_path)};
    std::vector<double> expected(g.points());
    for (int k = 0; k < g.slices(); ++k)
        for (int j = 0; j < g.rows(); ++j)
            std::memcpy(expected.data() + g.index(0, g.rows() - 1 - j, k),
                        bytes->data() + header.size() + 8 * (std::size_t(k) * g.rows() + j) * g.cols(),
                        8 * std::size_t(g.cols()));
    return {compare_field_values(expected, compared.field, compared.tolerance), 0};
}

}  // namespace fortu
