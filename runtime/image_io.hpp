// runtime/image_io.hpp — image files (PNG, TIFF, EXR, ...) through OpenImageIO, which lives in
// a plug-in module loaded on first use.
//
// Why a module: Debian's OpenImageIO links ~260 libraries (ffmpeg, GDAL, x265, ...); linking
// it into fortu maps them into every run, ~120 MiB resident before any work, which would
// drown the engines' own memory (a 7866-node model on 1024² needs tens of MiB). So the
// OpenImageIO code is built as `libfortu_image.so` next to the binary and dlopen'ed only by
// runs that read or write an image.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fortu {

struct ImageComparison;  // image_compare.hpp

/// One image, or one part of a multi-part file (a 3D EXR has one part per slice).
struct ImageLayer {
    int cols = 0;
    int rows = 0;
    std::vector<std::string> channels;   ///< channel names; their count is the channel count
    bool is_float = false;               ///< float32 samples, else uint8
    const void* pixels = nullptr;        ///< interleaved per pixel, row 0 at the top
    std::vector<std::pair<std::string, std::string>> text_attributes;
    std::vector<std::pair<std::string, float>> float_attributes;
};

/// An image read back: float samples, interleaved per pixel, row 0 at the top.
struct ImageData {
    int cols = 0;
    int rows = 0;
    std::vector<std::string> channels;
    std::vector<float> pixels;
};

/// Writes `layers` to `path` (the format follows its extension; several layers make a
/// multi-part file). One 8-bit layer to .png is encoded by libpng (png_writer.hpp) without
/// loading the module; otherwise OpenImageIO encodes one layer into memory and the bytes go through
/// write_file_atomically(), so every write is checked (libpng does not report a full disk);
/// a multi-part EXR is written by OpenEXR, which checks its writes, through
/// write_atomically(). Throws OutputError.
void write_image_file(const std::string& path, const std::vector<ImageLayer>& layers);

/// Reads the first image of `file`; nullopt with `error` set when it cannot. An image of more
/// than `max_pixels` pixels is refused from its header, before any pixel is decoded.
std::optional<ImageData> read_image(const std::string& file, std::string& error,
                                    std::size_t max_pixels = 1u << 26);

/// The interface the module exports (`fortu_image_module()`); versioned so a stale module
/// from an older build is refused instead of misread.
struct ImageModule {
    int version;
    /// Writes `layers` to `file`; "" or OpenImageIO's reason. For multi-part files, which
    /// OpenImageIO 2.4 cannot write into memory.
    std::string (*write)(const std::string& file, const std::vector<ImageLayer>& layers);
    /// Encodes one layer in the format `file` names into `bytes`; "" or the reason.
    std::string (*encode)(const std::string& file, const std::vector<ImageLayer>& layers,
                          std::vector<unsigned char>& bytes);
    bool (*read)(const std::string& file, ImageData& out, std::string& error, std::size_t max_pixels);
    /// image_compare.hpp's comparison and diff image, on OpenImageIO's ImageBufAlgo.
    ImageComparison (*compare)(const std::string& expected, const std::string& actual, double tolerance);
    std::string (*write_difference)(const std::string& expected, const std::string& actual, int subimage,
                                    const std::string& file);
};
inline constexpr int kImageModuleVersion = 3;

/// The loaded module, or nullptr with `error` set (why it cannot be found or loaded).
const ImageModule* image_module(std::string& error);

}  // namespace fortu
