// grammar/parse.hpp — the grammar layer's one entry point: script text in, AST out.
// Syntax errors go to a DiagnosticSink; the parser recovers at statement boundaries.
#pragma once

#include "grammar/ast.hpp"
#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"

namespace fortu {

/// Parses a whole script; syntax errors go to `sink` (recovering at statement boundaries
/// so one run reports several). Returns the statements it could build.
ast::Script parse_script(const SourceFile& source, DiagnosticSink& sink);

}  // namespace fortu
