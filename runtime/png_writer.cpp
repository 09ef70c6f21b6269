// runtime/png_writer.cpp — libpng's simplified write API (png_image_write_to_memory): no
// setjmp/longjmp in our code, errors come back in png_image.message.
#include "runtime/png_writer.hpp"

#include <png.h>

#include <fmt/format.h>

#include <memory>
#include <new>

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
    // One compression into a buffer of libpng's worst-case size, left uninitialised so that
    // only the pages the compressed stream reaches are touched; asking for the size first
    // (a null buffer) compresses the whole picture twice (half of a 1024² sign picture's
    // write time). The measuring call stays for a size that does not fit the type.
    png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(image);
    if (size > PNG_IMAGE_DATA_SIZE(image)) {
        const std::unique_ptr<unsigned char[]> buffer(new (std::nothrow) unsigned char[size]);
        if (buffer) {
            if (!png_image_write_to_memory(&image, buffer.get(), &size, 0, pixels, 0, nullptr))
                return fmt::format("libpng: {}", image.message);
            bytes.assign(buffer.get(), buffer.get() + size);
            png_image_free(&image);
            return {};
        }
    }
    size = 0;
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
