// interp/header_domain.cpp — the header comment's ranges as the model's, with a note.
#include "interp/header_domain.hpp"

#include "grammar/domain_comment.hpp"

#include <fmt/format.h>

namespace fortu {

void apply_domain_comment(const SourceFile& source, Model& model, DiagnosticSink& sink) {
    const int axes = static_cast<int>(model.arguments.size());
    for (int a = 0; a < axes; ++a)
        if (model.ranges[a]) return;
    const std::optional<DomainComment> comment = read_domain_comment(source);
    if (!comment) return;
    std::string ranges;
    for (int a = 0; a < axes; ++a) {
        if (!comment->ranges[a]) continue;
        const auto [lo, hi] = *comment->ranges[a];
        model.ranges[a] = AxisRange{lo, hi};
        ranges += fmt::format("{}{} [{}, {}]", ranges.empty() ? "" : ", ", model.arguments[a], lo, hi);
    }
    if (ranges.empty()) return;
    Diagnostic note;
    note.severity = Severity::Note;
    note.range = comment->where;
    note.message = fmt::format("the domain {} comes from this header comment (RANOK half-extents); "
                               "--domain overrides it", ranges);
    model.domain_note = render(note);
    sink.report(note);
}

}  // namespace fortu
