// cli/data_paths.hpp — where fortu finds its data folders: the INCLUDE search path and the
// stdlib, the examples and bench/models (`fortu bench`), the shared data (prospero.vm).
//
// Why: explicit, documented places, so a build tree anywhere, an installed tree under any
// prefix (or a copy of one) and a Debian package all find them. Each data folder is, in
// order: its environment variable if set (FORTU_STDLIB, FORTU_EXAMPLES, FORTU_BENCH_MODELS,
// FORTU_SHARED_DIR); else the installed one relative to the executable
// (BIN/../share/fortu/...) if it exists; else the build tree's (stdlib) or source tree's copy,
// configured at build time (fortu_config.hpp.in). INCLUDE searches the script's folder, then
// -I folders, then FORTU_PATH's (colon-separated), then the stdlib.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace fortu {

/// The folders INCLUDE searches after the script's own and the -I ones: FORTU_PATH's, then
/// the stdlib (CompileOptions::include_dirs).
std::vector<std::string> stdlib_dirs();
/// `include_dirs` (from -I / --include-dir, in the order given), then stdlib_dirs().
std::vector<std::string> include_search_path(const std::vector<std::string>& include_dirs);
/// The papers' example models (`fortu bench --paper`, `--performance`).
std::filesystem::path examples_dir();
/// bench/models (floz64.vm, `fortu bench --performance`).
std::filesystem::path bench_models_dir();
/// The shared data folder with prospero.vm (`fortu bench --performance`).
std::filesystem::path shared_data_dir();
/// `fortu --version`.
std::string version_text();

}  // namespace fortu
