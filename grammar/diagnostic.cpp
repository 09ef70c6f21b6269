// grammar/diagnostic.cpp — the one diagnostic renderer and the sink that collects them.
// Format (ninja/clang style): `path:line:col: error: message`, the source line verbatim,
// a caret line `^~~` under the range, then `note: hint` when there is a hint.
#include "grammar/diagnostic.hpp"

#include <algorithm>

namespace fortu {
namespace {

const char* severity_word(Severity severity) {
    switch (severity) {
    case Severity::Error: return "error";
    case Severity::Warning: return "warning";
    case Severity::Note: return "note";
    }
    return "error";
}

bool is_utf8_continuation(char c) {
    return (static_cast<unsigned char>(c) & 0xC0) == 0x80;
}

// The caret line under `text` for the range. Columns count bytes, but a terminal shows a
// UTF-8 character as one cell and expands tabs itself: so continuation bytes add nothing
// and a tab is copied, which keeps the caret under the right character.
/// Longest source excerpt a diagnostic shows, in bytes.
constexpr int kShownLineWidth = 120;

std::string caret_line(std::string_view text, const SourceRange& range) {
    const int last_column = static_cast<int>(text.size()) + 1;   // just after the line
    const int column = std::clamp(range.begin.column, 1, last_column);
    std::string out;
    for (int i = 0; i < column - 1; ++i) {
        const char c = text[static_cast<size_t>(i)];
        if (c == '\t') {
            out += '\t';
        } else if (!is_utf8_continuation(c)) {
            out += ' ';
        }
    }
    out += '^';
    if (range.end.line == range.begin.line && range.end.column > column) {
        const int end = std::min(range.end.column, last_column);
        for (int i = column; i < end - 1; ++i) {
            if (!is_utf8_continuation(text[static_cast<size_t>(i)])) {
                out += '~';
            }
        }
    }
    return out;
}

}  // namespace

std::string render(const Diagnostic& diagnostic) {
    std::string out;
    const SourceRange& range = diagnostic.range;
    if (range.file != nullptr) {
        out += range.file->path();
        out += ':' + std::to_string(range.begin.line) + ':' + std::to_string(range.begin.column);
        out += ": ";
    }
    out += severity_word(diagnostic.severity);
    out += ": ";
    out += diagnostic.message;
    out += '\n';
    if (range.file != nullptr) {
        // A long line (a generated model, binary garbage) is shown as a window around the
        // caret; control bytes are shown as '?' so they cannot drive the terminal.
        std::string_view text = range.file->line(range.begin.line);
        SourceRange shown = range;
        std::string prefix, suffix;
        if (text.size() > kShownLineWidth) {
            std::size_t start = static_cast<std::size_t>(std::max(0, range.begin.column - 1 - kShownLineWidth / 2));
            start = std::min(start, text.size() - kShownLineWidth);
            while (start > 0 && is_utf8_continuation(text[start])) --start;
            std::size_t end = start + kShownLineWidth;
            while (end < text.size() && is_utf8_continuation(text[end])) ++end;
            if (start > 0) prefix = "...";
            if (end < text.size()) suffix = "...";
            const int shift = static_cast<int>(prefix.size()) - static_cast<int>(start);
            shown.begin.column += shift;
            shown.end.column += shift;
            text = text.substr(start, end - start);
        }
        std::string line = prefix + std::string(text) + suffix;
        for (char& c : line)
            if ((static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f) c = '?';
        out += line;
        out += '\n';
        out += caret_line(line, shown);
        out += '\n';
    }
    if (!diagnostic.hint.empty()) {
        out += "note: ";
        out += diagnostic.hint;
        out += '\n';
    }
    return out;
}

void DiagnosticSink::report(Diagnostic diagnostic) {
    if (diagnostic.severity == Severity::Error) {
        ++error_count_;
    }
    diagnostics_.push_back(std::move(diagnostic));
}

void DiagnosticSink::error(const SourceRange& range, std::string message, std::string hint) {
    report(Diagnostic{Severity::Error, range, std::move(message), std::move(hint)});
}

void DiagnosticSink::warning(const SourceRange& range, std::string message, std::string hint) {
    report(Diagnostic{Severity::Warning, range, std::move(message), std::move(hint)});
}

void DiagnosticSink::note(const SourceRange& range, std::string message) {
    report(Diagnostic{Severity::Note, range, std::move(message), {}});
}

std::string DiagnosticSink::render_all() const {
    std::string out;
    for (const Diagnostic& diagnostic : diagnostics_) {
        out += render(diagnostic);
    }
    return out;
}

}  // namespace fortu
