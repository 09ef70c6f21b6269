// grammar/source.cpp — SourceFile: a script's bytes, loaded verbatim, and its line table.
// Lines end at LF, CRLF (Windows) or a lone CR (classic Mac OS), as in the lexer; the
// terminator is not part of the line.
#include "grammar/source.hpp"

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace fortu {

SourceFile::SourceFile(std::string path, std::string text)
    : path_(std::move(path)), text_(std::move(text)) {
    // An empty file still has one (empty) line, so every position has a line to show.
    line_starts_.push_back(0);
    for (size_t i = 0; i < text_.size(); ++i) {
        const bool crlf = text_[i] == '\r' && i + 1 < text_.size() && text_[i + 1] == '\n';
        const bool ends_line = (text_[i] == '\n' || text_[i] == '\r') && !crlf;
        if (ends_line && i + 1 < text_.size()) {
            line_starts_.push_back(static_cast<uint32_t>(i + 1));
        }
    }
}

std::shared_ptr<SourceFile> SourceFile::load(const std::string& path, std::string& error) {
    // fopen() succeeds on a directory on Linux and the read fails later with a vaguer
    // message, so ask first; a device or pipe could give bytes forever (/dev/zero).
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!ec && std::filesystem::is_directory(status)) {
        error = "cannot read '" + path + "': is a directory";
        return nullptr;
    }
    if (!ec && !std::filesystem::is_regular_file(status)) {
        error = "cannot read '" + path + "': not a regular file";
        return nullptr;
    }
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (file == nullptr) {
        error = "cannot read '" + path + "': " + std::strerror(errno);
        return nullptr;
    }
    std::string text;
    char buffer[1 << 16];
    size_t n = 0;
    bool too_large = false;
    while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) {
        if (text.size() + n > kMaxBytes) {
            too_large = true;
            break;
        }
        text.append(buffer, n);
    }
    const bool failed = std::ferror(file) != 0;
    const int saved_errno = errno;
    std::fclose(file);
    if (too_large) {
        error = "cannot read '" + path + "': larger than " + std::to_string(kMaxBytes >> 20) +
                " MiB, which no script needs";
        return nullptr;
    }
    if (failed) {
        error = "cannot read '" + path + "': " + std::strerror(saved_errno);
        return nullptr;
    }
    error.clear();
    return std::make_shared<SourceFile>(path, std::move(text));
}

std::string_view SourceFile::line(int line) const {
    if (line < 1 || line > line_count()) {
        return {};
    }
    const size_t begin = line_starts_[static_cast<size_t>(line - 1)];
    size_t end = text_.find_first_of("\r\n", begin);
    if (end == std::string::npos) {
        end = text_.size();
    }
    return std::string_view(text_).substr(begin, end - begin);
}

}  // namespace fortu
