// runtime/png_writer.cpp — libpng's simplified write API (png_image_write_to_memory): no
// setjmp/longjmp in our code, errors come back in png_image.message.
#include "runtime/png_writer.hpp"

#include <png.h>

#include <fmt/format.h>

#include <array>
#include <memory>
#include <new>

namespace fortu {
namespace {

/// The pixels of an RGB picture as a palette (3 bytes a colour, in order of first use) and an
/// index a pixel, if it has at most 256 colours; false otherwise. Why: a sign picture has
/// three or four colours, and libpng filters and zlib compresses a third of the bytes or less
/// (prospero.vm's 1024² sign run: 669 M → 286 M instructions in all); every PNG reader expands
/// a palette to the same colours.
bool palette_of(const std::uint8_t* rgb, std::size_t pixels, std::vector<std::uint8_t>& palette,
                std::uint8_t* indices) {
    constexpr std::size_t kSlots = 1024;   // open addressing, at most a quarter full
    std::array<std::uint32_t, kSlots> keys{};   // colour + 1, 0 for empty
    std::array<std::uint8_t, kSlots> index_of{};
    palette.clear();
    std::uint32_t last_key = 0;
    std::uint8_t last_index = 0;
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint8_t* p = rgb + 3 * i;
        const std::uint32_t key = (std::uint32_t(p[0]) << 16 | std::uint32_t(p[1]) << 8 | p[2]) + 1;
        if (key != last_key) {
            std::size_t slot = (key * 2654435761u) >> 22;   // the top 10 bits
            while (keys[slot] != 0 && keys[slot] != key) slot = (slot + 1) % kSlots;
            if (keys[slot] == 0) {
                if (palette.size() == 3 * 256) return false;
                keys[slot] = key;
                index_of[slot] = static_cast<std::uint8_t>(palette.size() / 3);
                palette.insert(palette.end(), p, p + 3);
            }
            last_key = key;
            last_index = index_of[slot];
        }
        indices[i] = last_index;
    }
    return true;
}

/// `image` (its format set) of `pixels` compressed into `bytes`; "" or the reason it cannot.
std::string compress(png_image& image, const void* pixels, const void* colormap, std::vector<unsigned char>& bytes) {
    // One compression into a buffer of libpng's worst-case size, left uninitialised so that
    // only the pages the compressed stream reaches are touched; asking for the size first
    // (a null buffer) compresses the whole picture twice (half of a 1024² sign picture's
    // write time). The measuring call stays for a size that does not fit the type.
    png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(image);
    if (size > PNG_IMAGE_DATA_SIZE(image)) {
        const std::unique_ptr<unsigned char[]> buffer(new (std::nothrow) unsigned char[size]);
        if (buffer) {
            if (!png_image_write_to_memory(&image, buffer.get(), &size, 0, pixels, 0, colormap))
                return fmt::format("libpng: {}", image.message);
            bytes.assign(buffer.get(), buffer.get() + size);
            png_image_free(&image);
            return {};
        }
    }
    size = 0;
    if (!png_image_write_to_memory(&image, nullptr, &size, 0, pixels, 0, colormap))
        return fmt::format("libpng: {}", image.message);
    bytes.resize(size);
    if (!png_image_write_to_memory(&image, bytes.data(), &size, 0, pixels, 0, colormap))
        return fmt::format("libpng: {}", image.message);
    bytes.resize(size);
    png_image_free(&image);
    return {};
}

}  // namespace

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
    if (channels == 3) {
        // Uninitialised: a picture of many colours gives up after its first rows, and the
        // pages it did not reach are never touched.
        const std::size_t count = std::size_t(cols) * rows;
        const std::unique_ptr<std::uint8_t[]> indices(new (std::nothrow) std::uint8_t[count]);
        std::vector<std::uint8_t> palette;
        if (indices && palette_of(pixels, count, palette, indices.get())) {
            image.format = PNG_FORMAT_RGB_COLORMAP;
            image.colormap_entries = static_cast<png_uint_32>(palette.size() / 3);
            return compress(image, indices.get(), palette.data(), bytes);
        }
    }
    return compress(image, pixels, nullptr, bytes);
}

}  // namespace fortu
