// cli/python/errors.hpp — fortu's errors as Python exceptions: a model's diagnostics become
// fortu.FortuError, whose text is exactly what the command line prints and which carries
// the diagnostics as fortu.Diagnostic objects; a bad request (grid size, engine, ...)
// becomes ValueError with the command line's message.
#pragma once

#include "grammar/diagnostic.hpp"

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace fortu::python {

/// One diagnostic as Python sees it (fortu.Diagnostic).
struct DiagnosticView {
    std::string severity;      ///< "error", "warning" or "note"
    std::string file;          ///< "" for a diagnostic without a location
    int line = 0, column = 0, end_line = 0, end_column = 0;
    std::string message;
    std::vector<std::string> notes;   ///< the hint (`note: ...` line), if any
    std::string text;                 ///< rendered as the command line prints it
};

std::vector<DiagnosticView> diagnostic_views(const std::vector<Diagnostic>& diagnostics);

/// Defines fortu.FortuError and fortu.Diagnostic, and translates UsageError to ValueError.
void register_errors(pybind11::module_& module);

/// Raises fortu.FortuError: its message the errors and warnings rendered as the command line
/// prints them (notes left out, as `fortu run` and `fortu eval` do), `.diagnostics` all of them.
[[noreturn]] void raise_fortu_error(const std::vector<Diagnostic>& diagnostics);

}  // namespace fortu::python
