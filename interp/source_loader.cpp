// interp/source_loader.cpp — the disk loader of source_loader.hpp.
#include "interp/source_loader.hpp"

#include <filesystem>

namespace fortu {

bool DiskSourceLoader::exists(const std::string& path) const {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string DiskSourceLoader::identity(const std::string& path) const {
    std::error_code ec;
    auto c = std::filesystem::weakly_canonical(path, ec);
    return ec ? path : c.string();
}

std::shared_ptr<SourceFile> DiskSourceLoader::load_script(const std::string& path, std::string& error) const {
    return SourceFile::load(path, error);
}

std::optional<ImageTable> DiskSourceLoader::load_image(const std::string& path, std::string& error,
                                                      std::size_t max_pixels) const {
    return read_image_table(path, error, max_pixels);
}

const SourceLoader& disk_source_loader() {
    static const DiskSourceLoader loader;
    return loader;
}

}  // namespace fortu
