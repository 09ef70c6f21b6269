// cli/mpi_module.cpp — the MPI plug-in, libfortu_mpi.so (mpi_module.hpp): World's calls on
// Open MPI's C API.
#include "cli/mpi_module.hpp"

#include <mpi.h>

namespace fortu {
namespace {

std::string init(int& rank, int& size) {
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS)
        return "MPI_Init_thread failed";
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    return "";
}

void finalize() { MPI_Finalize(); }
void barrier() { MPI_Barrier(MPI_COMM_WORLD); }

void abort(int status) { MPI_Abort(MPI_COMM_WORLD, status); }

void gather(const double* values, int count, double* all) {
    MPI_Gather(values, count, MPI_DOUBLE, all, count, MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

struct Counter {
    MPI_Win window;
    std::int64_t* base = nullptr;
};

void* counter_create() {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    auto* counter = new Counter;
    MPI_Win_allocate(rank == 0 ? sizeof(std::int64_t) : 0, sizeof(std::int64_t), MPI_INFO_NULL, MPI_COMM_WORLD,
                     &counter->base, &counter->window);
    if (rank == 0) *counter->base = 0;
    MPI_Barrier(MPI_COMM_WORLD);   // the counter is 0 before anyone draws
    MPI_Win_lock_all(0, counter->window);
    return counter;
}

std::uint64_t counter_next(void* opaque) {
    auto* counter = static_cast<Counter*>(opaque);
    const std::int64_t one = 1;
    std::int64_t got = 0;
    MPI_Fetch_and_op(&one, &got, MPI_INT64_T, 0, 0, MPI_SUM, counter->window);
    MPI_Win_flush(0, counter->window);
    return std::uint64_t(got);
}

void counter_free(void* opaque) {
    auto* counter = static_cast<Counter*>(opaque);
    MPI_Win_unlock_all(counter->window);
    MPI_Win_free(&counter->window);
    delete counter;
}

constexpr MpiModule kModule{kMpiModuleVersion, &init,   &finalize,     &barrier,     &abort,
                            &gather,           &counter_create, &counter_next, &counter_free};

}  // namespace
}  // namespace fortu

extern "C" void* fortu_mpi_module() { return const_cast<fortu::MpiModule*>(&fortu::kModule); }
