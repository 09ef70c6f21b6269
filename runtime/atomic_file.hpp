// runtime/atomic_file.hpp — every output file is written to a temporary in the same directory
// and renamed over the destination, so a failed or interrupted run never leaves a half file
// (architecture.md "Command line"). The one helper all writers use.
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <utility>

namespace fortu {

/// The byte sink handed to stream writers by write_file_atomically(). Every failed write
/// throws OutputError naming the destination and the system's reason.
class OutputFile {
public:
    OutputFile(std::FILE* file, std::string destination)
        : file_(file), destination_(std::move(destination)) {}

    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }

private:
    std::FILE* file_;
    std::string destination_;
};

/// Writes `path` atomically. `write` receives the name of a fresh, empty temporary in the same
/// directory — `.NAME.tmpXXXXXX.EXT`, keeping the real extension last so that OpenImageIO
/// picks the format — and fills it; the temporary is then renamed over `path`. If `write`
/// throws or the rename fails, the temporary is removed, `path` is left untouched and an
/// OutputError is thrown (an OutputError from `write` passes through; any other exception
/// becomes OutputError(path, what())).
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temp_path)>& write);

/// write_atomically() for writers that stream bytes: `write` fills an OutputFile; errors on
/// writing, flushing or closing become an OutputError with the system's reason.
void write_file_atomically(const std::string& path, const std::function<void(OutputFile&)>& write);

}  // namespace fortu
