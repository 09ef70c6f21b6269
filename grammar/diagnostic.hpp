// grammar/diagnostic.hpp — the one Diagnostic type and its renderer.
// Rendering follows the house style: `file:line:col: error: message`, the source line,
// then a caret under the range (`^~~~`), then an optional `note:`/hint line.
#pragma once

#include "grammar/source.hpp"

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace fortu {

enum class Severity { Error, Warning, Note };

struct Diagnostic {
    Severity severity = Severity::Error;
    SourceRange range;     ///< file == nullptr: a diagnostic without a location
    std::string message;
    std::string hint;      ///< rendered as a trailing `note: <hint>` line when not empty
};

/// Renders one diagnostic (with source line and caret when it has a location).
std::string render(const Diagnostic& diagnostic);

/// Collects diagnostics in order; counts errors.
class DiagnosticSink {
public:
    void report(Diagnostic diagnostic);
    void error(const SourceRange& range, std::string message, std::string hint = {});
    void warning(const SourceRange& range, std::string message, std::string hint = {});
    void note(const SourceRange& range, std::string message);

    int error_count() const { return error_count_; }
    bool has_errors() const { return error_count_ > 0; }
    const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
    /// All diagnostics rendered, in order.
    std::string render_all() const;
    void clear() { diagnostics_.clear(); error_count_ = 0; }
    /// Keeps a file alive as long as the sink, so diagnostics pointing into it can be
    /// rendered after whoever loaded it (an INCLUDE) is gone.
    void retain(std::shared_ptr<const SourceFile> file) { retained_.push_back(std::move(file)); }

private:
    std::vector<Diagnostic> diagnostics_;
    std::vector<std::shared_ptr<const SourceFile>> retained_;
    int error_count_ = 0;
};

}  // namespace fortu
