// cli/mpi_module.hpp — the table the MPI plug-in, libfortu_mpi.so (mpi_module.cpp), gives
// World (mpi_world.cpp): the few MPI calls a bricked run makes.
//
// Why a plug-in: Open MPI (with its run-time, hwloc and libevent) was mapped and relocated by
// every run, though only a run started by mpirun uses it (runtime/plugin_loader.hpp). It is
// loaded with RTLD_GLOBAL: Open MPI's components, which it opens itself, resolve libmpi's
// symbols through the global scope.
#pragma once

#include <cstdint>
#include <string>

namespace fortu {

struct MpiModule {
    int version;
    /// MPI_Init_thread (MPI_THREAD_SERIALIZED) with this process's rank and the job's size;
    /// "" or the reason it failed.
    std::string (*init)(int& rank, int& size);
    void (*finalize)();
    void (*barrier)();
    void (*abort)(int status);   ///< does not return
    /// Every rank's `count` values, concatenated in rank order into `all` on rank 0.
    void (*gather)(const double* values, int count, double* all);
    /// A job-wide counter (one-sided fetch-and-add on rank 0's window); collective.
    void* (*counter_create)();
    std::uint64_t (*counter_next)(void* counter);
    void (*counter_free)(void* counter);
};
inline constexpr int kMpiModuleVersion = 1;

}  // namespace fortu
