// runtime/vdb.cpp — loads libfortu_vdb.so on first use and writes through it.
#include "runtime/vdb.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/output_error.hpp"
#include "runtime/plugin_loader.hpp"

#ifndef FORTU_VDB_MODULE_BUILD_PATH
#define FORTU_VDB_MODULE_BUILD_PATH ""
#endif

namespace fortu {

const VdbModule* vdb_module(std::string& error) {
    static LazyPlugin plugin({"libfortu_vdb.so", "FORTU_VDB_MODULE", FORTU_VDB_MODULE_BUILD_PATH, "fortu_vdb_module",
                              "(fortu builds it next to its binary when OpenVDB is installed: apt-get install "
                              "libopenvdb-dev, then rebuild)",
                              kVdbModuleVersion});
    return static_cast<const VdbModule*>(plugin.get(error));
}

void write_vdb(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    std::string error;
    const VdbModule* module = vdb_module(error);
    if (!module) throw OutputError(target.path, error);
    std::string bytes;
    if (std::string e = module->encode(field, options.vdb_band, bytes); !e.empty()) throw OutputError(target.path, e);
    write_file_atomically(target.path, [&](OutputFile& out) { out.write(bytes); });
}

}  // namespace fortu
