// interp/header_domain.hpp — deciding whether a RANOK header comment sets the model's domain.
//
// Why: most RANOK scripts give their box only in a first-lines comment (domain_comment.hpp);
// ignoring it renders [-1, 1]³, all outside, without a word. The comment is the weakest
// source: ARGUMENT ranges and RECTANGLE win, and --domain wins over all (the command line
// says so when it uses the comment, with the note made here).
#pragma once

#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "interp/model.hpp"

namespace fortu {

/// When the script gives no range to any argument and its header comment gives some, sets
/// those ranges in `model` with the note that says so (also reported to `sink`).
void apply_domain_comment(const SourceFile& source, Model& model, DiagnosticSink& sink);

}  // namespace fortu
