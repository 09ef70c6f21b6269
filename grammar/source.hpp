// grammar/source.hpp — a script's text and positions in it.
// Every diagnostic and AST node points into a SourceFile by 1-based line and byte column.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {

/// The bytes of one script, kept verbatim (comments may hold cp1251 or any other bytes).
class SourceFile {
public:
    SourceFile(std::string path, std::string text);

    /// Reads a regular file of at most kMaxBytes; returns nullptr and sets `error` when it
    /// cannot be read (a device such as /dev/zero or a larger file is refused before reading).
    static std::shared_ptr<SourceFile> load(const std::string& path, std::string& error);
    /// No script comes near this; a larger file is a mistake (a data file, a device).
    static constexpr std::size_t kMaxBytes = 4u << 20;

    const std::string& path() const { return path_; }
    const std::string& text() const { return text_; }
    /// Number of lines (a final line without '\n' counts).
    int line_count() const { return static_cast<int>(line_starts_.size()); }
    /// The text of a 1-based line without its line terminator ("" when out of range).
    std::string_view line(int line) const;

private:
    std::string path_;
    std::string text_;
    std::vector<uint32_t> line_starts_;
};

/// A position: 1-based line, 1-based byte column.
struct SourcePos {
    int line = 1;
    int column = 1;
};

/// A half-open range [begin, end) inside one file; `end` may equal `begin` (a point).
struct SourceRange {
    const SourceFile* file = nullptr;
    SourcePos begin;
    SourcePos end;
};

}  // namespace fortu
