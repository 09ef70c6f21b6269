// runtime/image_io.cpp — finds and loads libfortu_image.so on first use.
#include "runtime/image_io.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/oiio_util.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_path.hpp"
#include "runtime/plugin_loader.hpp"
#include "runtime/png_writer.hpp"

#include <dlfcn.h>
#include <filesystem>
#include <mutex>

#ifndef FORTU_IMAGE_MODULE_BUILD_PATH
#define FORTU_IMAGE_MODULE_BUILD_PATH ""
#endif

namespace fortu {
namespace {

constexpr const char* kModuleName = "libfortu_image.so";

struct Loaded {
    const ImageModule* module = nullptr;
    std::string error;
};

/// $FORTU_IMAGE_MODULE, next to the binary or in the installed plug-in folder, next to the
/// shared object this code is linked
/// into (the installed Python module), then where the build put it (tests run from other folders).
Loaded load_module() {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("FORTU_IMAGE_MODULE")) candidates.emplace_back(env);
    for (std::string& path : plugin_candidates(kModuleName)) candidates.push_back(std::move(path));
    Dl_info self{};
    if (dladdr(reinterpret_cast<void*>(&load_module), &self) && self.dli_fname)
        candidates.push_back((std::filesystem::path(self.dli_fname).parent_path() / kModuleName).string());
    if (*FORTU_IMAGE_MODULE_BUILD_PATH) candidates.emplace_back(FORTU_IMAGE_MODULE_BUILD_PATH);
    std::error_code ec;
    Loaded result;
    for (const std::string& path : candidates) {
        if (!std::filesystem::exists(path, ec)) continue;
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            result.error = std::string("cannot load the image module: ") + dlerror();
            continue;
        }
        using Entry = const ImageModule* (*)();
        auto entry = reinterpret_cast<Entry>(dlsym(handle, "fortu_image_module"));
        const ImageModule* module = entry ? entry() : nullptr;
        if (!module || module->version != kImageModuleVersion) {
            result.error = "the image module '" + path + "' is from another build of fortu";
            continue;
        }
        result.module = module;
        return result;
    }
    if (result.error.empty())
        result.error = std::string("cannot find the image module ") + kModuleName +
                       " (it is built next to the fortu binary; set FORTU_IMAGE_MODULE to its path)";
    return result;
}

const Loaded& module() {
    static std::once_flag once;
    static Loaded loaded;
    std::call_once(once, [] { loaded = load_module(); });
    return loaded;
}

}  // namespace

const ImageModule* image_module(std::string& error) {
    const Loaded& m = module();
    if (!m.module) error = m.error;
    return m.module;
}

void write_image_file(const std::string& path, const std::vector<ImageLayer>& layers) {
    // An 8-bit PNG, the common case, through libpng without loading the module (png_writer.hpp).
    if (layers.size() == 1 && !layers[0].is_float && path_extension(path) == "png") {
        const ImageLayer& layer = layers[0];
        std::vector<unsigned char> bytes;
        const std::string error = encode_png(layer.cols, layer.rows, static_cast<int>(layer.channels.size()),
                                             static_cast<const std::uint8_t*>(layer.pixels), bytes);
        if (!error.empty()) throw OutputError(path, error);
        write_file_atomically(path, [&](OutputFile& file) { file.write(bytes.data(), bytes.size()); });
        return;
    }
    const Loaded& m = module();
    if (!m.module) throw OutputError(path, m.error);
    if (layers.size() > 1) {
        write_atomically(path, [&](const std::string& temp) {
            const std::string error = m.module->write(temp, layers);
            if (!error.empty()) throw OutputError(path, oiio_reason(error, temp, path));
        });
        return;
    }
    std::vector<unsigned char> bytes;
    const std::string error = m.module->encode(path, layers, bytes);
    if (!error.empty()) throw OutputError(path, oiio_reason(error, path, path));
    write_file_atomically(path, [&](OutputFile& file) { file.write(bytes.data(), bytes.size()); });
}

std::optional<ImageData> read_image(const std::string& file, std::string& error, std::size_t max_pixels) {
    const Loaded& m = module();
    if (!m.module) {
        error = m.error;
        return std::nullopt;
    }
    ImageData data;
    if (!m.module->read(file, data, error, max_pixels)) return std::nullopt;
    return data;
}

}  // namespace fortu
