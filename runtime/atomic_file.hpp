// runtime/atomic_file.hpp — every output file is written to a temporary in the same directory
// and renamed over the destination, so a failed or interrupted run never leaves a half file
// (architecture.md "Command line"). The one helper all writers use: every write, the flush,
// fsync and close are checked, so a full disk is an error and never a truncated file renamed
// over a good one.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <utility>

namespace fortu {

/// The byte sink handed to stream writers by write_file_atomically(): buffered write(2) on a
/// descriptor (no stdio, whose errors can go unseen). Every failed write throws OutputError
/// naming the destination and the system's reason.
class OutputFile {
public:
    OutputFile(int fd, std::string destination) : fd_(fd), destination_(std::move(destination)) {}
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }
    /// Writes out the buffer; throws OutputError on failure.
    void flush();

private:
    void write_through(const char* data, std::size_t size);

    int fd_;
    std::string destination_;
    std::string buffer_;
};

/// Writes `path` atomically. `write` receives the name of a fresh, empty temporary in the same
/// directory — `.NAME.tmp<PID>-XXXXXX.EXT` (temp_files.hpp), keeping the real extension last
/// so that OpenImageIO picks the format — and fills it; the temporary is then synced to disk
/// and renamed over `path`. Prefer write_file_atomically(): a writer given a path must check
/// its own writes. If `write`
/// throws or the rename fails, the temporary is removed, `path` is left untouched and an
/// OutputError is thrown (an OutputError from `write` passes through; any other exception
/// becomes OutputError(path, what())).
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temp_path)>& write);

/// write_atomically() for writers that stream bytes: `write` fills an OutputFile; errors on
/// writing, flushing, syncing or closing become an OutputError with the system's reason.
void write_file_atomically(const std::string& path, const std::function<void(OutputFile&)>& write);

}  // namespace fortu
