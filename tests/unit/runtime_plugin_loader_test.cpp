// tests/unit/runtime_plugin_loader_test.cpp — LazyPlugin: the reasons it gives, its version
// check, and the HDF5 plug-in's table loaded through it.
#include "runtime/plugin_loader.hpp"
#include "runtime/vtkhdf_module.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <optional>
#include <string>

using namespace fortu;

namespace {

/// The HDF5 plug-in where the build puts it (beside the fortu binary), its table asked for at
/// `version`; none when fortu was built without HDF5.
std::optional<LazyPlugin::Spec> built_hdf5_plugin(int version) {
    static const std::string path =
        (std::filesystem::path(FORTU_BINARY).parent_path() / "libfortu_hdf5.so").string();
    if (!std::filesystem::exists(path)) return std::nullopt;
    return LazyPlugin::Spec{"libfortu_hdf5.so", "FORTU_NO_SUCH_VARIABLE", path.c_str(), "fortu_hdf5_module", "",
                            version};
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
    const auto spec = built_hdf5_plugin(kVtkHdfModuleVersion + 1);
    if (!spec) return;
    LazyPlugin plugin(*spec);
    std::string error;
    CHECK(plugin.get(error) == nullptr);
    CHECK(error == "libfortu_hdf5.so is from another build of fortu");
}

TEST_CASE("the HDF5 plug-in loads and reports a file it cannot create as text") {
    const auto spec = built_hdf5_plugin(kVtkHdfModuleVersion);
    if (!spec) return;
    LazyPlugin plugin(*spec);
    std::string error;
    const auto* module = static_cast<const VtkHdfModule*>(plugin.get(error));
    REQUIRE(module != nullptr);
    CHECK(error.empty());
    VtkHdfLayout layout{"/nonexistent-folder/f.hdf", true, false, {2, 2, 2}, {0, 0, 0}, {1, 1, 1}, {"value"}};
    CHECK(module->open(layout, error) == nullptr);
    CHECK(error == "cannot create the file");
}
