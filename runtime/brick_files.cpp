// runtime/brick_files.cpp — partial files and done maps of bricked runs (brick_files.hpp).
#include "runtime/brick_files.hpp"

#include "runtime/output_error.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <climits>
#include <sys/uio.h>
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

void PartialFile::write_at(std::uint64_t offset, const std::vector<Piece>& pieces) {
    std::vector<iovec> io;
    for (const Piece& p : pieces) io.push_back({const_cast<void*>(p.data), p.size});
    std::size_t first = 0;
    while (first < io.size()) {
        const int count = int(std::min<std::size_t>(io.size() - first, IOV_MAX));
        const ssize_t n = ::pwritev(fd_, io.data() + first, count, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw OutputError(destination_, n < 0 ? system_reason() : "no space written");
        offset += std::uint64_t(n);
        // Past the pieces written whole; a piece written in part goes on from where it stopped.
        for (std::size_t left = std::size_t(n); left > 0;) {
            if (left >= io[first].iov_len) {
                left -= io[first].iov_len;
                ++first;
            } else {
                io[first].iov_base = static_cast<char*>(io[first].iov_base) + left;
                io[first].iov_len -= left;
                left = 0;
            }
        }
    }
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

void DoneMap::record(const std::vector<std::size_t>& bricks) {
    if (bricks.empty()) return;
    std::string lines;
    for (const std::size_t brick : bricks) {
        lines += std::to_string(brick);
        lines += '\n';
    }
    write_all(fd_, lines.data(), lines.size(), 0, false, path_);   // one O_APPEND write: whole lines
    if (::fdatasync(fd_) != 0) throw OutputError(path_, system_reason());
}

void DoneMap::remove() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    ::unlink(path_.c_str());
}


DoneRecorder::DoneRecorder(DoneMap& map, std::function<void()> sync_output, double period, std::size_t batch)
    : map_(map), sync_output_(std::move(sync_output)), period_(period), batch_(batch), thread_([this] { loop(); }) {}

DoneRecorder::~DoneRecorder() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
}

void DoneRecorder::finished(std::size_t brick) {
    std::lock_guard lock(mutex_);
    if (error_) std::rethrow_exception(error_);
    pending_.push_back(brick);
    if (pending_.size() == batch_) wake_.notify_all();
}

void DoneRecorder::flush() {
    std::unique_lock lock(mutex_);
    wake_.wait(lock, [&] { return !syncing_; });   // a batch in flight finishes first
    if (error_) std::rethrow_exception(error_);
    record_batch(lock);
    if (error_) std::rethrow_exception(error_);
}

/// Syncs and records the pending bricks; the lock is released while the disk works.
void DoneRecorder::record_batch(std::unique_lock<std::mutex>& lock) {
    if (pending_.empty()) return;
    std::vector<std::size_t> batch;
    batch.swap(pending_);   // taken before the sync: each was written before it starts
    syncing_ = true;
    lock.unlock();
    std::exception_ptr error;
    try {
        sync_output_();
        map_.record(batch);
    } catch (...) {
        error = std::current_exception();
    }
    lock.lock();
    syncing_ = false;
    if (error && !error_) error_ = error;
    wake_.notify_all();
}

void DoneRecorder::loop() {
    std::unique_lock lock(mutex_);
    while (!stop_) {
        wake_.wait_for(lock, std::chrono::duration<double>(period_),
                       [&] { return stop_ || (!syncing_ && pending_.size() >= batch_); });
        if (stop_ || error_) break;
        if (!syncing_) record_batch(lock);
    }
}

}  // namespace fortu
