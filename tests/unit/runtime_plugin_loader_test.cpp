// tests/unit/runtime_plugin_loader_test.cpp — LazyPlugin: the reasons it gives, its version
// check, and the HDF5 plug-in's table loaded through it.
#include "runtime/plugin_loader.hpp"
#include "runtime/vtkhdf_module.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <string>

using namespace fortu;

namespace {

/// Where the build puts the plug-ins: beside the fortu binary.
std::string built_plugin(const char* file_name) {
    return (std::filesystem::path(FORTU_BINARY).parent_path() / file_name).string();
}

}  // namespace

TEST_CASE("a plug-in found nowhere names the file and the hint, every time it is asked") {
    LazyPlugin plugin({"libfortu_nowhere.so", "FORTU_NOWHERE_MODULE", "", "fortu_nowhere_module",
                       "(install nothing)", 1});
    std::string error;
    CHECK(plugin.get(error) == nullptr);
    CHECK(error == "cannot find libfortu_nowhere.so (install nothing)");
    error.clear();
    CHECK(plugin.get(error) == nullptr);
    CHECK(error == "cannot find libfortu_nowhere.so (install nothing)");
}

TEST_CASE("a plug-in whose table has another version is refused") {
    const std::string path = built_plugin("libfortu_hdf5.so");
    if (!std::filesystem::exists(path)) return;   // built without HDF5
    LazyPlugin plugin({"libfortu_hdf5.so", "FORTU_NO_SUCH_VARIABLE", path.c_str(), "fortu_hdf5_module", "",
                       kVtkHdfModuleVersion + 1});
    std::string error;
    CHECK(plugin.get(error) == nullptr);
    CHECK(error == "libfortu_hdf5.so is from another build of fortu");
}

TEST_CASE("the HDF5 plug-in loads and reports a file it cannot create as text") {
    const std::string path = built_plugin("libfortu_hdf5.so");
    if (!std::filesystem::exists(path)) return;   // built without HDF5
    LazyPlugin plugin({"libfortu_hdf5.so", "FORTU_NO_SUCH_VARIABLE", path.c_str(), "fortu_hdf5_module", "",
                       kVtkHdfModuleVersion});
    std::string error;
    const auto* module = static_cast<const VtkHdfModule*>(plugin.get(error));
    REQUIRE(module != nullptr);
    CHECK(error.empty());
    VtkHdfLayout layout{"/nonexistent-folder/f.hdf", true, false, {2, 2, 2}, {0, 0, 0}, {1, 1, 1}, {"value"}};
    CHECK(module->open(layout, error) == nullptr);
    CHECK(error == "cannot create the file");
}
