// cli/mpi_world.cpp — World over MPI when built with it (FORTU_HAVE_MPI), else one process.
#include "cli/mpi_world.hpp"

#include <cstdlib>

#ifdef FORTU_HAVE_MPI
#include <mpi.h>
#endif

namespace fortu {

World& World::get() {
    static World world;
    return world;
}

World::World() {
#ifdef FORTU_HAVE_MPI
    if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr) return;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    initialised_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
#endif
}

World::~World() {
#ifdef FORTU_HAVE_MPI
    if (initialised_) MPI_Finalize();
#endif
}

void World::barrier() {
#ifdef FORTU_HAVE_MPI
    if (initialised_) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

void World::abort(int status) {
#ifdef FORTU_HAVE_MPI
    if (initialised_) MPI_Abort(MPI_COMM_WORLD, status);
#endif
    std::exit(status);
}

std::vector<double> World::gather(const std::vector<double>& values) {
#ifdef FORTU_HAVE_MPI
    if (initialised_) {
        std::vector<double> all(rank_ == 0 ? values.size() * size_ : 0);
        MPI_Gather(values.data(), int(values.size()), MPI_DOUBLE, all.data(), int(values.size()), MPI_DOUBLE, 0,
                   MPI_COMM_WORLD);
        return all;
    }
#endif
    return values;
}

World::Counter::Counter(World& world) : world_(world) {
#ifdef FORTU_HAVE_MPI
    if (world.initialised_) {
        MPI_Win win;
        MPI_Win_allocate(world.rank_ == 0 ? sizeof(std::int64_t) : 0, sizeof(std::int64_t), MPI_INFO_NULL,
                         MPI_COMM_WORLD, &base_, &win);
        if (world.rank_ == 0) *base_ = 0;
        window_ = new MPI_Win(win);
        MPI_Barrier(MPI_COMM_WORLD);   // the counter is 0 before anyone draws
        MPI_Win_lock_all(0, win);
    }
#endif
}

World::Counter::~Counter() {
#ifdef FORTU_HAVE_MPI
    if (window_) {
        MPI_Win* win = static_cast<MPI_Win*>(window_);
        MPI_Win_unlock_all(*win);
        MPI_Win_free(win);
        delete win;
    }
#endif
}

std::uint64_t World::Counter::next() {
    std::lock_guard lock(world_.mpi_mutex());
#ifdef FORTU_HAVE_MPI
    if (window_) {
        const std::int64_t one = 1;
        std::int64_t got = 0;
        MPI_Win& win = *static_cast<MPI_Win*>(window_);
        MPI_Fetch_and_op(&one, &got, MPI_INT64_T, 0, 0, MPI_SUM, win);
        MPI_Win_flush(0, win);
        return std::uint64_t(got);
    }
#endif
    return local_++;
}

}  // namespace fortu
