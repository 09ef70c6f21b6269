// cli/data_paths.cpp — the data folders: environment variable, else the configured build or
// source folder if present, else the installed one (data_paths.hpp).
#include "cli/data_paths.hpp"

#include "cli/fortu_config.hpp"

#include <cstdlib>

namespace fortu {
namespace {

std::filesystem::path pick(const char* variable, const char* built, const char* installed) {
    if (const char* value = std::getenv(variable); value && *value) return value;
    std::error_code ec;
    if (std::filesystem::is_directory(built, ec)) return built;
    return installed;
}

}  // namespace

std::vector<std::string> stdlib_dirs() {
    return {pick("FORTU_STDLIB", config::kBuildStdlibDir, config::kInstallStdlibDir).string()};
}

std::filesystem::path examples_dir() {
    return pick("FORTU_EXAMPLES", config::kSourceExamplesDir, config::kInstallExamplesDir);
}

std::filesystem::path bench_models_dir() {
    return pick("FORTU_BENCH_MODELS", config::kSourceBenchModelsDir, config::kInstallBenchModelsDir);
}

std::filesystem::path shared_data_dir() {
    if (const char* shared = std::getenv("FORTU_SHARED_DIR"); shared && *shared)
        return std::filesystem::path(shared) / "data";
    return config::kSharedDataDir;
}

std::string version_text() { return std::string("fortu ") + config::kVersion + "\n"; }

}  // namespace fortu
