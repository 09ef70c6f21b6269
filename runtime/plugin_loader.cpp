// runtime/plugin_loader.cpp — dlopen of a plug-in module by its candidate paths.
#include "runtime/plugin_loader.hpp"

#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <vector>

#ifndef FORTU_PLUGIN_DIR_FROM_BIN
#define FORTU_PLUGIN_DIR_FROM_BIN "../lib/fortu"
#endif

namespace fortu {

std::vector<std::string> plugin_candidates(const std::string& file_name) {
    std::vector<std::string> candidates;
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return candidates;
    const std::filesystem::path bin = exe.parent_path();
    candidates.push_back((bin / file_name).string());
    candidates.push_back((bin.parent_path() / file_name).string());
    candidates.push_back((bin / FORTU_PLUGIN_DIR_FROM_BIN / file_name).lexically_normal().string());
    return candidates;
}

void* load_plugin_entry(const std::string& file_name, const char* env_variable, const std::string& build_path,
                        const char* entry, const std::string& missing_hint, std::string& error, bool global) {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv(env_variable)) candidates.emplace_back(env);
    for (std::string& path : plugin_candidates(file_name)) candidates.push_back(std::move(path));
    if (!build_path.empty()) candidates.push_back(build_path);
    error.clear();
    std::error_code ec;
    for (const std::string& path : candidates) {
        if (!std::filesystem::exists(path, ec)) continue;
        void* handle = dlopen(path.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
        if (!handle) {
            error = "cannot load " + path + ": " + dlerror();
            continue;
        }
        using Entry = void* (*)();
        auto function = reinterpret_cast<Entry>(dlsym(handle, entry));
        if (void* result = function ? function() : nullptr) return result;
        error = "'" + path + "' is not a fortu plug-in of this build";
    }
    if (error.empty()) error = "cannot find " + file_name + " " + missing_hint;
    return nullptr;
}

const void* LazyPlugin::get(std::string& error) {
    std::call_once(once_, [this] {
        const void* table = load_plugin_entry(spec_.file_name, spec_.env_variable, spec_.build_path, spec_.entry,
                                              spec_.missing_hint, error_, spec_.global);
        if (table && *static_cast<const int*>(table) != spec_.version) {
            error_ = std::string(spec_.file_name) + " is from another build of fortu";
        } else if (table) {
            table_ = table;
            error_.clear();   // an earlier candidate's failure, not this plug-in's
        }
    });
    error = error_;
    return table_;
}

}  // namespace fortu
