// interp/source_loader.hpp — where compile() gets the files a script names: INCLUDE'd scripts
// and IMAGE('...') pictures. From disk by default; tests pass an in-memory loader (as ninja's
// tests pass a VirtualFileSystem), so testing includes and images needs no real files.
#pragma once

#include "grammar/source.hpp"
#include "runtime/image_table.hpp"

#include <memory>
#include <optional>
#include <string>

namespace fortu {

class SourceLoader {
public:
    virtual ~SourceLoader() = default;

    /// True if `path` names a file (INCLUDE tries its candidate folders in order).
    virtual bool exists(const std::string& path) const = 0;
    /// One name per file whatever the path that reached it, so a library included twice
    /// (`lib.fortu`, `./lib.fortu`) is read once.
    virtual std::string identity(const std::string& path) const = 0;
    /// The script at `path`; nullptr and `error` (why, without the path) on failure.
    virtual std::shared_ptr<SourceFile> load_script(const std::string& path, std::string& error) const = 0;
    /// The picture at `path` as grey levels; nullopt and `error` (why) on failure, also when
    /// it has more than `max_pixels` pixels (found before decoding).
    virtual std::optional<ImageTable> load_image(const std::string& path, std::string& error,
                                                 std::size_t max_pixels) const = 0;
};

/// Files on disk: SourceFile::load, read_image_table (OpenImageIO), identity = the
/// canonical path.
class DiskSourceLoader final : public SourceLoader {
public:
    bool exists(const std::string& path) const override;
    std::string identity(const std::string& path) const override;
    std::shared_ptr<SourceFile> load_script(const std::string& path, std::string& error) const override;
    std::optional<ImageTable> load_image(const std::string& path, std::string& error,
                                         std::size_t max_pixels) const override;
};

/// The loader compile() uses when CompileOptions::loader is not set.
const SourceLoader& disk_source_loader();

}  // namespace fortu
