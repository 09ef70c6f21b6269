// runtime/png_writer.cpp — libpng's simplified write API (png_image_write_to_memory): no
// setjmp/longjmp in our code, errors come back in png_image.message.
#include "runtime/png_writer.hpp"

#include <png.h>

#include <fmt/format.h>

namespace fortu {

std::string encode_png(int cols, int rows, int channels, const std::uint8_t* pixels,
                       std::vector<unsigned char>& bytes) {
    static constexpr png_uint_32 kFormats[] = {PNG_FORMAT_GRAY, PNG_FORMAT_GA, PNG_FORMAT_RGB, PNG_FORMAT_RGBA};
    if (channels < 1 || channels > 4) return fmt::format("PNG holds 1 to 4 channels, not {}", channels);
    if (cols < 1 || rows < 1) return fmt::format("a {}x{} picture has no pixels", cols, rows);
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = static_cast<png_uint_32>(cols);
    image.height = static_cast<png_uint_32>(rows);
    image.format = kFormats[channels - 1];
    png_alloc_size_t size = 0;
    // The first call measures, the second writes.
    if (!png_image_write_to_memory(&image, nullptr, &size, 0, pixels, 0, nullptr))
        return fmt::format("libpng: {}", image.message);
    bytes.resize(size);
    if (!png_image_write_to_memory(&image, bytes.data(), &size, 0, pixels, 0, nullptr))
        return fmt::format("libpng: {}", image.message);
    bytes.resize(size);
    png_image_free(&image);
    return {};
}

}  // namespace fortu
