// interp/lower.hpp — checks a parsed script and lowers it to the IR, in one pass.
//
// Why one pass: FORTU's meaning is sequential (each use sees the latest definition before
// it, spec §2), so name resolution, section rules and lowering all walk the statements in
// order with the same scope; splitting them would mean building the scope twice. Every
// definition becomes IR nodes through Graph::make, which shares equal sub-expressions and
// folds constants, so a variable referenced ten times is still one node.
#pragma once

#include "grammar/diagnostic.hpp"
#include "grammar/source.hpp"
#include "interp/limits.hpp"
#include "interp/model.hpp"
#include "interp/source_loader.hpp"

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fortu {

struct CompileOptions {
    /// From the command line; wins over RSYSTEM statements in the script.
    std::optional<RSystem> rsystem;
    /// Folders searched by INCLUDE after the script's own folder: the stdlib, which the
    /// command line finds (cli/data_paths.hpp).
    std::vector<std::string> include_dirs;
    /// Reads INCLUDE'd scripts and IMAGE pictures; nullptr = from disk (disk_source_loader()).
    const SourceLoader* loader = nullptr;
    /// Values that replace top-level scalar CONSTANT definitions, by name (case-insensitive):
    /// the first definition of each is lowered as that number instead of its expression, so
    /// everything computed from it folds as if the script had been written with it (the
    /// Python module's per-call constants). A name no such definition has is an error.
    std::vector<std::pair<std::string, double>> constants;
    /// The compile-time budgets (limits.def); `--limit name=value` sets them.
    Limits limits;
};

/// Parses, checks and lowers a script. Errors, warnings and notes go to `sink`; returns
/// nullopt when there was any error.
std::optional<Model> compile(std::shared_ptr<const SourceFile> source,
                             const CompileOptions& options, DiagnosticSink& sink);

}  // namespace fortu
