// runtime/plugin_loader.hpp — finding and dlopen'ing one of fortu's plug-in modules
// (libfortu_image.so, libfortu_vdb.so) next to the binary, where the build put it, or where an
// environment variable says, and calling its entry point.
//
// Why: libraries with heavy dependency trees (OpenImageIO, OpenVDB) stay out of runs that do
// not use them (image_io.hpp says why that matters).
#pragma once

#include <string>
#include <vector>

namespace fortu {

/// Where a plug-in `file_name` may be, after its environment variable: beside the running
/// executable (/proc/self/exe; the build tree), its parent folder, and the installed layout's
/// plug-in folder relative to it (BIN/../lib/fortu, FORTU_PLUGIN_DIR_FROM_BIN), so a
/// package installed under any prefix finds its plug-ins.
std::vector<std::string> plugin_candidates(const std::string& file_name);

/// The value the module's `entry` function returns, or nullptr with `error` set: not found
/// (saying `missing_hint`), not loadable (dlerror), or without the entry.
/// Candidates: $`env_variable`, then plugin_candidates(), then `build_path`.
void* load_plugin_entry(const std::string& file_name, const char* env_variable, const std::string& build_path,
                        const char* entry, const std::string& missing_hint, std::string& error);

}  // namespace fortu
