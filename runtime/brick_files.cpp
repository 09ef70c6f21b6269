// runtime/brick_files.cpp — partial files and done maps of bricked runs (brick_files.hpp).
#include "runtime/brick_files.hpp"

#include "runtime/output_error.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace fortu {
namespace {

std::string system_reason() { return std::strerror(errno); }

void write_all(int fd, const char* data, std::size_t size, std::uint64_t offset, bool at_offset,
               const std::string& destination) {
    while (size > 0) {
        const ssize_t n = at_offset ? ::pwrite(fd, data, size, off_t(offset)) : ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw OutputError(destination, n < 0 ? system_reason() : "no space written");
        data += n;
        size -= std::size_t(n);
        offset += std::uint64_t(n);
    }
}

}  // namespace

std::string partial_path(const std::string& destination, const std::string& suffix) {
    const std::filesystem::path p(destination);
    std::string name = ".";   // appended, not "." + ...: GCC 12's -Wrestrict misfires on that
    name += p.filename().string();
    name += ".bricks";
    name += suffix;
    return (p.parent_path() / name).string();
}

std::string done_map_path(const std::string& destination) { return destination + ".done"; }

PartialFile::PartialFile(std::string path, std::string destination, bool keep)
    : path_(std::move(path)), destination_(std::move(destination)) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | (keep ? 0 : O_TRUNC), 0666);
    if (fd_ < 0) throw OutputError(destination_, system_reason());
}

PartialFile::~PartialFile() {
    if (fd_ >= 0) ::close(fd_);
}

void PartialFile::write_at(std::uint64_t offset, const void* data, std::size_t size) {
    write_all(fd_, static_cast<const char*>(data), size, offset, true, destination_);
}

std::uint64_t PartialFile::append(const void* data, std::size_t size) {
    const std::uint64_t at = this->size();
    write_at(at, data, size);
    return at;
}

std::uint64_t PartialFile::size() const {
    struct stat st {};
    if (::fstat(fd_, &st) != 0) throw OutputError(destination_, system_reason());
    return std::uint64_t(st.st_size);
}

void PartialFile::truncate(std::uint64_t size) {
    if (::ftruncate(fd_, off_t(size)) != 0) throw OutputError(destination_, system_reason());
}

void PartialFile::sync() {
    if (::fdatasync(fd_) != 0) throw OutputError(destination_, system_reason());
}

void PartialFile::commit() {
    if (::fsync(fd_) != 0) throw OutputError(destination_, system_reason());
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) throw OutputError(destination_, system_reason());
    if (::rename(path_.c_str(), destination_.c_str()) != 0) throw OutputError(destination_, system_reason());
}

DoneMap::DoneMap(const std::string& destination, const std::string& key, Mode mode)
    : path_(done_map_path(destination)), destination_(destination) {
    if (mode != Mode::Fresh) {
        std::ifstream in(path_);
        std::string first;
        if (in && std::getline(in, first)) {
            if (first != key)
                throw OutputError(destination_, "'" + path_ + "' was written by another run (model, grid, bricks or "
                                                "format differ); remove it or run without --resume");
            for (std::string line; std::getline(in, line);) {
                std::size_t brick = 0;
                std::istringstream words(line);
                if (words >> brick) done_.insert(brick);   // a torn last line is not a brick
            }
        }
    }
    const bool fresh = mode == Mode::Fresh;
    fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC | (fresh ? O_TRUNC : 0), 0666);
    if (fd_ < 0) throw OutputError(path_, system_reason());
    if (fresh) {
        const std::string line = key + "\n";
        write_all(fd_, line.data(), line.size(), 0, false, path_);
        if (::fdatasync(fd_) != 0) throw OutputError(path_, system_reason());
    }
}

DoneMap::~DoneMap() {
    if (fd_ >= 0) ::close(fd_);
}

void DoneMap::record(std::size_t brick) {
    const std::string line = std::to_string(brick) + "\n";
    write_all(fd_, line.data(), line.size(), 0, false, path_);   // one O_APPEND write: whole lines
    if (::fdatasync(fd_) != 0) throw OutputError(path_, system_reason());
}

void DoneMap::remove() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    ::unlink(path_.c_str());
}

}  // namespace fortu
