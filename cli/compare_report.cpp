// cli/compare_report.cpp — the text of `--compare` (compare_report.hpp).
#include "cli/compare_report.hpp"

#include "runtime/field_difference.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>

namespace fortu {
namespace {

std::string node_text(const Grid& g, std::size_t p) {
    const int col = static_cast<int>(p % g.cols()), row = static_cast<int>(p / g.cols() % g.rows());
    const int slice = static_cast<int>(p / (static_cast<std::size_t>(g.cols()) * g.rows()));
    if (g.dims == 3) return fmt::format("({}, {}, {})", g.x_at(col), g.y_at(row), g.z_at(slice));
    return fmt::format("({}, {})", g.x_at(col), g.y_at(row));
}

std::string nodes_text(std::size_t n) { return fmt::format("{} node{}", format_count(n), n == 1 ? "" : "s"); }

}  // namespace

std::string compare_report(const Field& result, const std::string& label, const Field& reference,
                           const std::string& reference_label) {
    const Grid& g = result.grid;
    const FieldDifference d = field_difference(result, reference);
    const std::string size = g.dims == 3 ? fmt::format("{}x{}x{}", g.cols(), g.rows(), g.slices())
                                         : fmt::format("{}x{}", g.cols(), g.rows());
    std::string text = fmt::format("{} against {} on {} = {}:\n", label, reference_label, size, nodes_text(g.points()));
    if (d.compared == 0) {
        text += "  no node where both values are finite\n";
    } else {
        text += fmt::format("  max |difference| {:.6g} at {} ({}: {:.17g}, {}: {:.17g}); largest |value| {:.6g}\n",
                            d.max, node_text(g, d.max_at), label, result.values[d.max_at], reference_label,
                            reference.values[d.max_at], d.reference_magnitude);
        text += fmt::format("  RMS difference {:.6g} over {}\n", d.rms, nodes_text(d.compared));
        text += fmt::format("  sign differs at {}", nodes_text(d.sign_differs));
        for (std::size_t i = 0; i < d.sign_examples.size(); ++i)
            text += (i == 0 ? ": " : ", ") + node_text(g, d.sign_examples[i]);
        if (d.sign_differs > d.sign_examples.size()) text += ", ...";
        text += "\n";
    }
    text += fmt::format("  invalid in only one of them: {}\n", nodes_text(d.invalid_in_one));
    return text;
}

}  // namespace fortu
