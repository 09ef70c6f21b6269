// runtime/atomic_file.cpp — temporary file next to the destination, then rename(2), which
// replaces the destination in one step on POSIX file systems.
#include "runtime/atomic_file.hpp"

#include "runtime/output_error.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>

#include <fcntl.h>
#include <unistd.h>

namespace fortu {
namespace {

namespace fs = std::filesystem;

std::string system_reason(int error) { return std::strerror(error); }

// Creates a new empty file `DIR/.NAME.tmpXXXXXX.EXT` (O_EXCL, so never someone else's file) and
// returns its name. The mode is 0666 less the umask, as for any new file.
std::string create_temporary(const std::string& path) {
    const fs::path destination(path);
    const std::string name = destination.filename().string();
    if (name.empty() || name == "." || name == "..") throw OutputError(path, "not a file name");
    const fs::path dir = destination.parent_path();
    const std::string extension = destination.extension().string();

    static constexpr char kAlphabet[] = "abcdefghijklmnopqrstuvwxyz0123456789";
    std::random_device seed;
    std::mt19937 random(seed());
    std::uniform_int_distribution<int> pick(0, sizeof kAlphabet - 2);
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string unique;
        for (int i = 0; i < 6; ++i) unique += kAlphabet[pick(random)];
        const std::string temp = (dir / ("." + name + ".tmp" + unique + extension)).string();
        const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return temp;
        }
        if (errno == EEXIST) continue;
        const int error = errno;
        const std::string shown = dir.empty() ? std::string(".") : dir.string();
        if (error == ENOENT) throw OutputError(path, "directory '" + shown + "' does not exist");
        if (error == ENOTDIR) throw OutputError(path, "'" + shown + "' is not a directory");
        throw OutputError(path, "cannot create a file in '" + shown + "': " + system_reason(error));
    }
    throw OutputError(path, "cannot find an unused temporary file name");
}

}  // namespace

void OutputFile::write(const void* data, std::size_t size) {
    if (size == 0) return;
    if (std::fwrite(data, 1, size, file_) != size) {
        throw OutputError(destination_, system_reason(errno));
    }
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temp_path)>& write) {
    const std::string temp = create_temporary(path);
    try {
        write(temp);
        if (::rename(temp.c_str(), path.c_str()) != 0) throw OutputError(path, system_reason(errno));
    } catch (const OutputError&) {
        std::remove(temp.c_str());
        throw;
    } catch (const std::exception& e) {
        std::remove(temp.c_str());
        throw OutputError(path, e.what());
    } catch (...) {
        std::remove(temp.c_str());
        throw;
    }
}

void write_file_atomically(const std::string& path, const std::function<void(OutputFile&)>& write) {
    write_atomically(path, [&](const std::string& temp) {
        std::FILE* file = std::fopen(temp.c_str(), "wb");
        if (!file) throw OutputError(path, system_reason(errno));
        try {
            OutputFile out(file, path);
            write(out);
        } catch (...) {
            std::fclose(file);
            throw;
        }
        const bool failed = std::fflush(file) != 0 || std::ferror(file);
        const int error = errno;
        if (std::fclose(file) != 0 || failed) throw OutputError(path, system_reason(failed ? error : errno));
    });
}

}  // namespace fortu
