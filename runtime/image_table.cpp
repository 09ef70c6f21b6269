// runtime/image_table.cpp — reading an image into a table of grey levels (through the image module).
// Integer formats are scaled to [0, 1] by OpenImageIO's float conversion, so an 8-bit and a
// 16-bit export of the same height map give the same table.
#include "runtime/image_table.hpp"

#include "runtime/image_io.hpp"

#include <algorithm>
#include <filesystem>

namespace fortu {

std::optional<ImageTable> read_image_table(const std::string& path, std::string& error,
                                           std::size_t max_pixels) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        error = "no such file";
        return std::nullopt;
    }
    std::optional<ImageData> image = read_image(path, error, max_pixels);
    if (!image) return std::nullopt;
    const int channels = static_cast<int>(image->channels.size());
    if (image->cols <= 0 || image->rows <= 0 || channels <= 0) {
        error = "not a 2D image";
        return std::nullopt;
    }
    // Colour channels only: a transparent border should not read as a dip in the height map.
    const auto alpha = std::find(image->channels.begin(), image->channels.end(), "A");
    const int alpha_channel = channels > 1 && alpha != image->channels.end()
                                  ? static_cast<int>(alpha - image->channels.begin()) : -1;
    const int colours = alpha_channel >= 0 ? channels - 1 : channels;
    ImageTable table;
    table.width = image->cols;
    table.height = image->rows;
    const std::size_t pixels = static_cast<std::size_t>(image->cols) * image->rows;
    table.values.reserve(pixels);
    for (std::size_t p = 0; p < pixels; ++p) {
        double sum = 0;
        for (int c = 0; c < channels; ++c)
            if (c != alpha_channel) sum += image->pixels[p * channels + c];
        table.values.push_back(sum / colours);
    }
    return table;
}

}  // namespace fortu
