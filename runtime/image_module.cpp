// runtime/image_module.cpp — the OpenImageIO plug-in (libfortu_image.so): the only code
// that includes OpenImageIO (with image_compare_oiio.cpp, linked into it). See image_io.hpp
// for why it is a module.
#include "runtime/image_compare.hpp"
#include "runtime/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <fmt/format.h>

namespace fortu {
namespace {

/// OpenImageIO starts worker-thread pools (its own and OpenEXR's) on first use. fortu writes
/// one image at a time, so they buy nothing; with no pool no threads outlive the write, which
/// also keeps LeakSanitizer's exit-time thread stop reliable in the asan build.
void single_threaded_once() {
    static const bool done = [] {
        OIIO::attribute("threads", 1);
        OIIO::attribute("exr_threads", -1);
        return true;
    }();
    (void)done;
}

// `proxy` (into memory) or the file itself: the caller writes the bytes with checked writes,
// since OpenImageIO's PNG and BMP writers do not report a failed write.
std::string write_layers_to(const std::string& file, const std::vector<ImageLayer>& layers,
                            OIIO::Filesystem::IOProxy* proxy) {
    if (layers.empty()) return "no image to write";
    auto out = OIIO::ImageOutput::create(file);
    if (!out) {
        std::string reason = OIIO::geterror();
        return reason.empty() ? "OpenImageIO cannot write this format" : reason;
    }
    std::vector<OIIO::ImageSpec> specs;
    for (const ImageLayer& layer : layers) {
        OIIO::ImageSpec spec(layer.cols, layer.rows, static_cast<int>(layer.channels.size()),
                             layer.is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        spec.channelnames = layer.channels;
        for (const auto& [name, value] : layer.text_attributes) spec.attribute(name, value);
        for (const auto& [name, value] : layer.float_attributes) spec.attribute(name, value);
        if (proxy) spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        specs.push_back(std::move(spec));
    }
    if (proxy && !out->supports("ioproxy")) return "OpenImageIO cannot write this format into memory";
    auto failed = [&] {
        std::string reason = out->geterror();
        return reason.empty() ? std::string("OpenImageIO reported an unknown error") : reason;
    };
    const int count = static_cast<int>(specs.size());
    if (count > 1 && !out->supports("multiimage")) return "this format holds one image only";
    if (!out->open(file, count, specs.data())) return failed();
    for (int i = 0; i < count; ++i) {
        if (i > 0 && !out->open(file, specs[i], OIIO::ImageOutput::AppendSubimage)) return failed();
        const OIIO::TypeDesc type = layers[i].is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
        if (!out->write_image(type, layers[i].pixels)) return failed();
    }
    if (!out->close()) return failed();
    return {};
}

std::string write_layers(const std::string& file, const std::vector<ImageLayer>& layers) {
    return write_layers_to(file, layers, nullptr);
}

std::string encode_layer(const std::string& file, const std::vector<ImageLayer>& layers,
                         std::vector<unsigned char>& bytes) {
    if (layers.size() != 1) return "one image at a time into memory";
    OIIO::Filesystem::IOVecOutput memory(bytes);
    return write_layers_to(file, layers, &memory);
}

bool read_first(const std::string& file, ImageData& data, std::string& error, std::size_t max_pixels) {
    auto in = OIIO::ImageInput::open(file);
    if (!in) {
        error = OIIO::geterror();
        if (error.empty()) error = "OpenImageIO cannot read it";
        return false;
    }
    const OIIO::ImageSpec& spec = in->spec();
    // From the header, before decoding: a small file may claim a huge picture.
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels <= 0 || spec.nchannels > 64) {
        error = fmt::format("not a 2D image ({}x{}x{}, {} channels)", spec.width, spec.height, spec.depth,
                            spec.nchannels);
        return false;
    }
    const std::size_t pixels = static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height);
    if (pixels > max_pixels) {
        error = fmt::format("the picture is {}x{}, more than {} pixels", spec.width, spec.height, max_pixels);
        return false;
    }
    data.cols = spec.width;
    data.rows = spec.height;
    data.channels = spec.channelnames;
    data.pixels.resize(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.pixels.data())) {
        error = in->geterror();
        if (error.empty()) error = "OpenImageIO could not decode it";
        return false;
    }
    in->close();
    return true;
}

constexpr ImageModule kModule{kImageModuleVersion, &write_layers, &encode_layer, &read_first, &oiio_compare_images,
                              &oiio_write_difference};

}  // namespace
}  // namespace fortu

extern "C" __attribute__((visibility("default"))) const fortu::ImageModule* fortu_image_module() {
    fortu::single_threaded_once();
    return &fortu::kModule;
}
