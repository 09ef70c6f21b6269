// tests/unit/memory_source_loader.hpp — an in-memory SourceLoader (ninja's VirtualFileSystem
// for FORTU): tests of INCLUDE and IMAGE give their files as strings and tables, so they need
// no real files and can see what compile() asked for.
#pragma once

#include "interp/source_loader.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace fortu::test {

class MemorySourceLoader final : public SourceLoader {
public:
    /// Adds (or replaces) a script; returns `path`.
    std::string add_script(const std::string& path, std::string text) {
        scripts_[normal(path)] = std::move(text);
        return path;
    }
    void add_image(const std::string& path, ImageTable table) { images_[normal(path)] = std::move(table); }

    bool exists(const std::string& path) const override {
        return scripts_.count(normal(path)) > 0 || images_.count(normal(path)) > 0;
    }
    std::string identity(const std::string& path) const override { return normal(path); }
    std::shared_ptr<SourceFile> load_script(const std::string& path, std::string& error) const override {
        loaded_.push_back(path);
        const auto it = scripts_.find(normal(path));
        if (it == scripts_.end()) {
            error = "no such script in memory";
            return nullptr;
        }
        return std::make_shared<SourceFile>(path, it->second);
    }
    std::optional<ImageTable> load_image(const std::string& path, std::string& error, std::size_t) const override {
        loaded_.push_back(path);
        const auto it = images_.find(normal(path));
        if (it == images_.end()) {
            error = "no such picture in memory";
            return std::nullopt;
        }
        return it->second;
    }

    /// Every path load_script / load_image was asked for, in order.
    const std::vector<std::string>& loaded() const { return loaded_; }

private:
    static std::string normal(const std::string& path) { return std::filesystem::path(path).lexically_normal().string(); }

    std::map<std::string, std::string> scripts_;
    std::map<std::string, ImageTable> images_;
    mutable std::vector<std::string> loaded_;
};

}  // namespace fortu::test
