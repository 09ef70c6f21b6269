// cli/fv_steps.cpp — the files of `--steps DIR` (fv_steps.hpp).
#include "cli/fv_steps.hpp"

#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/picture.hpp"

#include <filesystem>
#include <fmt/format.h>

namespace fortu {

StepWriter::StepWriter(std::string dir, std::size_t steps, OutputOptions options)
    : dir_(std::move(dir)), width_(std::max<int>(2, static_cast<int>(fmt::format("{}", steps).size()))),
      options_(std::move(options)) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec || !std::filesystem::is_directory(dir_))
        throw OutputError(dir_, ec ? ec.message() : "not a folder");
}

void StepWriter::operator()(const EvalStep& step) {
    const std::string stem = (std::filesystem::path(dir_) / fmt::format("{:0{}}_{}", step.index, width_, step.name)).string();
    write_field(step.values, stem + ".png", options_);
    files_.push_back(stem + ".png");
    if (!step.palette) {
        // The EXR writer refits the planes from the values: unquantised, the stored planes
        // pass through those values, so this equals them to rounding.
        write_mimages(step.values, stem + "_m.exr", options_);
        files_.push_back(stem + "_m.exr");
        return;
    }
    const Grid& g = step.values.grid;
    const int slice = picture_slice(g, options_.slice);
    if (slice < 0) throw OutputError(stem + ".png", fmt::format("slice {} is out of range 0..{}", options_.slice, g.slices() - 1));
    const int channels = *step.palette == Palette::Grey8 ? 1 : 3;
    const std::size_t first = g.index(0, 0, slice), plane = static_cast<std::size_t>(g.cols()) * g.rows();
    for (std::size_t k = 0; k < step.components.size(); ++k) {
        std::vector<std::uint8_t> pixels;
        pixels.reserve(plane * channels);
        for (std::size_t p = first; p < first + plane; ++p) {
            const std::uint32_t m = palette_encode(step.components[k][p], *step.palette);
            if (channels == 1) pixels.push_back(static_cast<std::uint8_t>(m));
            else for (std::uint8_t byte : rgb24_pack(m)) pixels.push_back(byte);
        }
        const std::string path = fmt::format("{}_m{}.png", stem, k + 1);
        write_image_8bit(path, g.cols(), g.rows(), channels, pixels, options_);
        files_.push_back(path);
    }
}

}  // namespace fortu
