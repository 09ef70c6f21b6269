// runtime/atomic_file.cpp — temporary file next to the destination, fsync, then rename(2),
// which replaces the destination in one step on POSIX file systems. Raw write(2) rather than
// stdio so that every short write and error is seen (and a test can fail write() with ENOSPC
// through an LD_PRELOAD shim).
#include "runtime/atomic_file.hpp"

#include "runtime/output_error.hpp"
#include "runtime/temp_files.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>

#include <fcntl.h>
#include <unistd.h>

namespace fortu {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kBufferSize = 1 << 16;

std::string system_reason(int error) { return std::strerror(error); }

struct Temporary {
    std::string path;
    int slot;   ///< in temp_files' table, registered before the file exists: no window for a signal
};

// Creates a new empty file `DIR/.NAME.tmp<PID>-XXXXXX.EXT` (O_EXCL, so never someone else's
// file) and returns its name. The mode is 0666 less the umask, as for any new file.
Temporary create_temporary(const std::string& path) {
    const fs::path destination(path);
    const std::string name = destination.filename().string();
    if (name.empty() || name == "." || name == "..") throw OutputError(path, "not a file name");
    const fs::path dir = destination.parent_path();
    remove_stale_temporaries(dir.string());

    static constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    std::random_device seed;
    std::mt19937 random(seed());
    std::uniform_int_distribution<int> pick(0, sizeof kAlphabet - 2);
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string unique;
        for (int i = 0; i < 6; ++i) unique += kAlphabet[pick(random)];
        const std::string temp = (dir / temporary_file_name(name, unique)).string();
        const int slot = remember_temporary(temp);
        const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return {temp, slot};
        }
        const int error = errno;
        forget_temporary(slot);
        if (error == EEXIST) continue;
        const std::string shown = dir.empty() ? std::string(".") : dir.string();
        if (error == ENOENT) throw OutputError(path, "directory '" + shown + "' does not exist");
        if (error == ENOTDIR) throw OutputError(path, "'" + shown + "' is not a directory");
        throw OutputError(path, "cannot create a file in '" + shown + "': " + system_reason(error));
    }
    throw OutputError(path, "cannot find an unused temporary file name");
}

// fsync(2) of a file a writer filled by name, so that a delayed write error (NFS, a full
// thin volume) shows up before the rename rather than after.
void sync_file(const std::string& temp, const std::string& path) {
    const int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw OutputError(path, system_reason(errno));
    const bool failed = ::fsync(fd) != 0;
    const int error = errno;
    ::close(fd);
    if (failed) throw OutputError(path, system_reason(error));
}

// The temporary is removed however the write ends: by an exception here, or by a signal
// (temp_files.hpp) while it is registered.
class TemporaryGuard {
public:
    explicit TemporaryGuard(Temporary temp) : temp_(std::move(temp.path)), slot_(temp.slot) {}
    ~TemporaryGuard() {
        if (!kept_) ::unlink(temp_.c_str());
        forget_temporary(slot_);
    }
    TemporaryGuard(const TemporaryGuard&) = delete;
    TemporaryGuard& operator=(const TemporaryGuard&) = delete;
    void renamed() { kept_ = true; }

private:
    std::string temp_;
    int slot_;
    bool kept_ = false;
};

}  // namespace

void OutputFile::write_through(const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd_, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            throw OutputError(destination_, system_reason(errno));
        }
        if (n == 0) throw OutputError(destination_, system_reason(ENOSPC));
        data += n;
        size -= static_cast<std::size_t>(n);
    }
}

void OutputFile::write(const void* data, std::size_t size) {
    if (size == 0) return;
    const char* bytes = static_cast<const char*>(data);
    if (buffer_.size() + size <= kBufferSize) {
        buffer_.append(bytes, size);
        return;
    }
    flush();
    if (size >= kBufferSize) write_through(bytes, size);
    else buffer_.assign(bytes, size);
}

void OutputFile::flush() {
    write_through(buffer_.data(), buffer_.size());
    buffer_.clear();
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temp_path)>& write) {
    Temporary created = create_temporary(path);
    const std::string temp = created.path;
    TemporaryGuard guard(std::move(created));
    try {
        write(temp);
        sync_file(temp, path);
        if (::rename(temp.c_str(), path.c_str()) != 0) throw OutputError(path, system_reason(errno));
        guard.renamed();
    } catch (const OutputError&) {
        throw;
    } catch (const std::exception& e) {
        throw OutputError(path, e.what());
    }
}

void write_file_atomically(const std::string& path, const std::function<void(OutputFile&)>& write) {
    write_atomically(path, [&](const std::string& temp) {
        const int fd = ::open(temp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
        if (fd < 0) throw OutputError(path, system_reason(errno));
        try {
            OutputFile out(fd, path);
            write(out);
            out.flush();
        } catch (...) {
            ::close(fd);
            throw;
        }
        if (::close(fd) != 0) throw OutputError(path, system_reason(errno));   // write_atomically then fsyncs it
    });
}

}  // namespace fortu
