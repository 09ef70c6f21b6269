// cli/mpi_world.hpp — the processes of a run: this one alone, or the ranks of an `mpirun`
// job, with the few collective steps a bricked run needs.
//
// Why here and this small: MPI is loaded (the plug-in libfortu_mpi.so, mpi_module.hpp) and
// started only when Open MPI's launcher started us (OMPI_COMM_WORLD_SIZE is set), so a plain
// `fortu run` pays nothing for it; a build without MPI (-DFORTU_MPI=OFF, or no
// libopenmpi-dev) has the same interface with one process.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

namespace fortu {

struct MpiModule;

class World {
public:
    /// The world of this process: MPI initialised on first call when launched by mpirun.
    static World& get();

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool distributed() const { return size_ > 1; }

    void barrier();
    /// Ends every rank (after an error on this one), with `status`.
    [[noreturn]] void abort(int status);

    /// Held around every MPI call made while threads run (MPI_THREAD_SERIALIZED): the
    /// brick counter's and a parallel HDF5 writer's.
    std::mutex& mpi_mutex() { return mpi_mutex_; }

    /// Every rank's `values` (the same count on each), concatenated in rank order, on rank 0
    /// (empty elsewhere).
    std::vector<double> gather(const std::vector<double>& values);

    /// A counter all ranks draw from: each call returns the next number, 0, 1, 2, ... once
    /// across the job (MPI one-sided fetch-and-add on rank 0's window: the rank-0 queue
    /// without a process serving it). Collective to create; one per run.
    class Counter {
    public:
        explicit Counter(World& world);
        ~Counter();
        Counter(const Counter&) = delete;
        Counter& operator=(const Counter&) = delete;
        std::uint64_t next();

    private:
        World& world_;
        void* shared_ = nullptr;      ///< the plug-in's counter, when distributed
        std::uint64_t local_ = 0;     ///< alone: a plain counter
    };

private:
    World();
    ~World();
    int rank_ = 0;
    int size_ = 1;
    const MpiModule* mpi_ = nullptr;   ///< set once MPI is initialised
    std::mutex mpi_mutex_;
};

}  // namespace fortu
