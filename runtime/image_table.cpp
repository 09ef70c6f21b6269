// runtime/image_table.cpp — reading an image into a table of grey levels through OpenImageIO.
// Integer formats are scaled to [0, 1] by OpenImageIO's float conversion, so an 8-bit and a
// 16-bit export of the same height map give the same table.
#include "runtime/image_table.hpp"

#include <OpenImageIO/imageio.h>

#include <filesystem>

namespace fortu {

std::optional<ImageTable> read_image_table(const std::string& path, std::string& error) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        error = "no such file";
        return std::nullopt;
    }
    auto input = OIIO::ImageInput::open(path);
    if (!input) {
        error = OIIO::geterror();
        if (error.empty()) error = "not an image OpenImageIO can read";
        return std::nullopt;
    }
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
        error = "not a 2D image";
        return std::nullopt;
    }
    std::vector<float> pixels(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) {
        error = input->geterror();
        if (error.empty()) error = "cannot decode the pixels";
        return std::nullopt;
    }
    // Colour channels only: a transparent border should not read as a dip in the height map.
    const int colours = spec.alpha_channel >= 0 && spec.nchannels > 1 ? spec.nchannels - 1 : spec.nchannels;
    ImageTable table;
    table.width = spec.width;
    table.height = spec.height;
    table.values.reserve(static_cast<std::size_t>(spec.width) * spec.height);
    for (std::size_t p = 0; p < static_cast<std::size_t>(spec.width) * spec.height; ++p) {
        double sum = 0;
        for (int c = 0, k = 0; c < spec.nchannels && k < colours; ++c) {
            if (c == spec.alpha_channel) continue;
            sum += pixels[p * spec.nchannels + c];
            ++k;
        }
        table.values.push_back(sum / colours);
    }
    return table;
}

}  // namespace fortu
