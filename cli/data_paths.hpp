// cli/data_paths.hpp — where fortu finds its data folders: the stdlib (INCLUDE), the
// examples and bench/models (`fortu bench`), the shared data (prospero.vm).
//
// Why: explicit, documented places instead of walking up from the binary, so a build tree
// anywhere and an installed binary both find them. Each folder is, in order: its
// environment variable if set (FORTU_STDLIB, FORTU_EXAMPLES, FORTU_BENCH_MODELS,
// FORTU_SHARED_DIR); else the build tree's / source tree's copy, configured at build time
// (fortu_config.hpp.in), if it exists; else the installed one (share/fortu/...).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace fortu {

/// The folders INCLUDE searches after the script's own (CompileOptions::include_dirs).
std::vector<std::string> stdlib_dirs();
/// The papers' example models (`fortu bench --paper`, `--performance`).
std::filesystem::path examples_dir();
/// bench/models (floz64.vm, `fortu bench --performance`).
std::filesystem::path bench_models_dir();
/// The shared data folder with prospero.vm (`fortu bench --performance`).
std::filesystem::path shared_data_dir();
/// `fortu --version`.
std::string version_text();

}  // namespace fortu
