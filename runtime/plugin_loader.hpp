// runtime/plugin_loader.hpp — finding and dlopen'ing one of fortu's plug-in modules
// (libfortu_image.so, libfortu_vdb.so) next to the binary, where the build put it, or where an
// environment variable says, and calling its entry point.
//
// Why: libraries with heavy dependency trees (OpenImageIO, OpenVDB) stay out of runs that do
// not use them (image_io.hpp says why that matters).
#pragma once

#include <string>

namespace fortu {

/// The value the module's `entry` function returns, or nullptr with `error` set: not found
/// (saying `missing_hint`), not loadable (dlerror), or without the entry.
/// Candidates: $`env_variable`, then beside /proc/self/exe and its parent folder, then
/// `build_path`.
void* load_plugin_entry(const std::string& file_name, const char* env_variable, const std::string& build_path,
                        const char* entry, const std::string& missing_hint, std::string& error);

}  // namespace fortu
