// runtime/plugin_loader.hpp — finding and dlopen'ing one of fortu's plug-in modules
// (libfortu_image.so, libfortu_vdb.so, libfortu_hdf5.so, libfortu_mpi.so) next to the binary,
// where the build put it, or where an environment variable says, and calling its entry point.
//
// Why: libraries with heavy dependency trees (OpenImageIO, OpenVDB, HDF5 with libcurl, GnuTLS
// and Kerberos, Open MPI) stay out of runs that do not use them (image_io.hpp says why that
// matters): linked into the binary, HDF5 and Open MPI alone mapped 45 libraries and 7.5 MiB of
// resident pages into every run, and their relocation was most of a small run's start-up.
#pragma once

#include <mutex>
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
/// `global`: the module's symbols (and its libraries') serve libraries loaded after it
/// (RTLD_GLOBAL: Open MPI's own components resolve libmpi's symbols so).
void* load_plugin_entry(const std::string& file_name, const char* env_variable, const std::string& build_path,
                        const char* entry, const std::string& missing_hint, std::string& error, bool global = false);

/// One plug-in, loaded on the first get() (thread-safe) and kept. Its entry returns a table
/// whose first member is its `int version`; a table of another version is refused.
class LazyPlugin {
public:
    struct Spec {
        const char* file_name;
        const char* env_variable;
        const char* build_path;
        const char* entry;
        const char* missing_hint;
        int version;
        bool global = false;
    };
    explicit LazyPlugin(Spec spec) : spec_(spec) {}

    /// The module's table, or nullptr with the reason in `error`.
    const void* get(std::string& error);

private:
    Spec spec_;
    std::once_flag once_;
    const void* table_ = nullptr;
    std::string error_;
};

}  // namespace fortu
