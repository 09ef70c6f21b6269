// interp/vm_import.hpp — reads a model in the Prospero/Fidget `.vm` SSA text format
// (`name op args...`, `#` comments) into a Model with the same IR as a FORTU script.
// Why: the benchmark models of the field (../shared/data/*.vm) then run through every
// engine and output fortu has; their sign convention is negative inside, so the root is negated.
#pragma once

#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "interp/model.hpp"

#include <memory>
#include <optional>
#include <string_view>

namespace fortu {

/// True when `path` names a .vm model (by extension, case-insensitive).
bool is_vm_path(std::string_view path);

/// Parses a .vm file. Arguments are X, Y (and Z when var-z occurs), ranges [-1, 1]; the
/// root is the negated last value (FORTU: positive inside). The R0 formulas
/// a + b ∓ sqrt(a² + b²) become R-operations (same value bit for bit), so they prune. Errors go to `sink`, located at
/// the offending token; returns nullopt on any error.
std::optional<Model> import_vm(std::shared_ptr<const SourceFile> source, DiagnosticSink& sink);

}  // namespace fortu
