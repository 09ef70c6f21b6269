// cli/data_paths.cpp — the data folders: environment variable, else the installed folder
// beside the executable if present, else the build or source tree's (data_paths.hpp).
#include "cli/data_paths.hpp"

#include "cli/fortu_config.hpp"
#include "cli/option_table.hpp"

#include <cstdlib>

namespace fortu {
namespace {

namespace fs = std::filesystem;

/// share/fortu/NAME of the installed layout, relative to /proc/self/exe ("" when unknown).
fs::path installed(const char* name) {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    return (exe.parent_path() / config::kDataDirFromBin / "fortu" / name).lexically_normal();
}

fs::path pick(const char* variable, const char* name, const char* built) {
    if (const char* value = std::getenv(variable); value && *value) return value;
    std::error_code ec;
    const fs::path beside_binary = installed(name);
    if (!beside_binary.empty() && fs::is_directory(beside_binary, ec)) return beside_binary;
    if (fs::is_directory(built, ec)) return built;
    return beside_binary.empty() ? fs::path(built) : beside_binary;   // named in "searched:" notes
}

}  // namespace

std::vector<std::string> stdlib_dirs() {
    std::vector<std::string> dirs;
    if (const char* path = std::getenv("FORTU_PATH"); path && *path)
        for (const std::string& dir : split_value(path, ':'))
            if (!dir.empty()) dirs.push_back(dir);   // an empty entry is a stray colon, not "."
    dirs.push_back(pick("FORTU_STDLIB", "stdlib", config::kBuildStdlibDir).string());
    return dirs;
}

std::vector<std::string> include_search_path(const std::vector<std::string>& include_dirs) {
    std::vector<std::string> dirs = include_dirs;
    for (std::string& dir : stdlib_dirs()) dirs.push_back(std::move(dir));
    return dirs;
}

fs::path examples_dir() { return pick("FORTU_EXAMPLES", "examples", config::kSourceExamplesDir); }

fs::path bench_models_dir() { return pick("FORTU_BENCH_MODELS", "bench/models", config::kSourceBenchModelsDir); }

fs::path shared_data_dir() {
    if (const char* shared = std::getenv("FORTU_SHARED_DIR"); shared && *shared) return fs::path(shared) / "data";
    return config::kSharedDataDir;
}

std::string version_text() { return std::string("fortu ") + config::kVersion + "\n"; }

}  // namespace fortu
