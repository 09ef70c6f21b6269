// runtime/brick_files.hpp — the files of a bricked run that survive a crash: the output's
// partial file (`.NAME.bricks`, renamed over NAME when every brick is in) and the done map
// (`NAME.done`), one line per finished brick, so `--resume` computes only the missing ones.
//
// Why: Open MPI aborts the whole job when one rank dies, and a 2048³ run is hours. A brick
// is recorded as done only after its bytes are on disk (fdatasync of the partial file,
// then of the done map), so a kill at any moment loses at most the bricks in flight and
// those of the last second. Syncs go in batches, on a thread of their own (DoneRecorder):
// two syncs per brick made the disk, not the arithmetic, set a run's pace. The
// first line of the done map is the run's key (grid, bricks, model, format): a resume of
// a different run is refused instead of mixing two results.
#pragma once

#include <cstddef>
#include <cstdint>
#include <set>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace fortu {

/// A file written at offsets (pwrite), checked; errors throw OutputError naming `destination`.
class PartialFile {
public:
    /// Opens `path` (created if missing; truncated unless `keep`).
    PartialFile(std::string path, std::string destination, bool keep);
    ~PartialFile();
    PartialFile(const PartialFile&) = delete;
    PartialFile& operator=(const PartialFile&) = delete;

    void write_at(std::uint64_t offset, const void* data, std::size_t size);
    /// Writes `pieces` one after another from `offset` (pwritev: one call for many rows).
    struct Piece {
        const void* data;
        std::size_t size;
    };
    void write_at(std::uint64_t offset, const std::vector<Piece>& pieces);
    /// Appends at the end (for record files); returns the offset written at.
    std::uint64_t append(const void* data, std::size_t size);
    std::uint64_t size() const;
    void truncate(std::uint64_t size);
    void sync();
    /// Syncs, closes and renames the file over the destination.
    void commit();
    const std::string& path() const { return path_; }

private:
    std::string path_, destination_;
    int fd_ = -1;
};

/// `.NAME.bricks` beside `destination` (with `suffix`, e.g. `.r3` for rank 3's part).
std::string partial_path(const std::string& destination, const std::string& suffix = "");
/// `NAME.done` beside the destination.
std::string done_map_path(const std::string& destination);

/// The done map: the run's key, then finished brick numbers, appended line by line.
class DoneMap {
public:
    /// Fresh: starts an empty map with the key. Resume: reads the bricks already done (a map
    /// with another key throws OutputError: "... was written by another run"). Join: as
    /// Resume, for a second process of the same run (MPI ranks after rank 0).
    enum class Mode { Fresh, Resume, Join };
    DoneMap(const std::string& destination, const std::string& key, Mode mode);
    ~DoneMap();
    DoneMap(const DoneMap&) = delete;
    DoneMap& operator=(const DoneMap&) = delete;

    const std::set<std::size_t>& done() const { return done_; }
    /// Records `bricks` (durably: one O_APPEND write of whole lines, then fdatasync). Safe
    /// from several processes; done() is not updated.
    void record(const std::vector<std::size_t>& bricks);
    /// Removes the map (the output is complete).
    void remove();

private:
    std::string path_, destination_;
    int fd_ = -1;
    std::set<std::size_t> done_;
};

/// Records finished bricks in the done map in batches: workers hand over each brick after
/// writing it; a thread of its own, every `period` seconds or once `batch` bricks wait,
/// takes them, syncs the output (`sync_output`: every byte written before it is then on
/// disk) and appends them to the map. So the map never names a brick whose data could
/// still be lost, and a kill loses at most a second or `batch` bricks of work per process.
class DoneRecorder {
public:
    DoneRecorder(DoneMap& map, std::function<void()> sync_output, double period = 1.0, std::size_t batch = 64);
    /// Stops the thread; bricks not yet flushed are not recorded (they are recomputed).
    ~DoneRecorder();
    DoneRecorder(const DoneRecorder&) = delete;
    DoneRecorder& operator=(const DoneRecorder&) = delete;

    /// A brick whose data is written. Thread-safe; rethrows an error of the sync thread.
    void finished(std::size_t brick);
    /// Syncs and records every brick handed over so far (the end of this process's bricks).
    void flush();

private:
    void loop();
    void record_batch(std::unique_lock<std::mutex>& lock);

    DoneMap& map_;
    std::function<void()> sync_output_;
    double period_;
    std::size_t batch_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::vector<std::size_t> pending_;
    bool stop_ = false;
    bool syncing_ = false;
    std::exception_ptr error_;
    std::thread thread_;
};

}  // namespace fortu
