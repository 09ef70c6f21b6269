// cli/mpi_world.cpp — World over the MPI plug-in when launched by mpirun, else one process.
#include "cli/mpi_world.hpp"

#include "cli/mpi_module.hpp"
#include "runtime/plugin_loader.hpp"

#include <cstdlib>
#include <fmt/format.h>
#include <iostream>

#ifndef FORTU_MPI_MODULE_BUILD_PATH
#define FORTU_MPI_MODULE_BUILD_PATH ""
#endif

namespace fortu {

World& World::get() {
    static World world;
    return world;
}

World::World() {
    if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr) return;
    static LazyPlugin plugin({"libfortu_mpi.so", "FORTU_MPI_MODULE", FORTU_MPI_MODULE_BUILD_PATH, "fortu_mpi_module",
                              "(fortu builds it next to its binary when Open MPI is installed: apt-get install "
                              "libopenmpi-dev openmpi-bin, then rebuild)",
                              kMpiModuleVersion, /*global=*/true});
    std::string error;
    const auto* mpi = static_cast<const MpiModule*>(plugin.get(error));
    if (mpi) error = mpi->init(rank_, size_);
    if (!error.empty()) {
        // Started by mpirun, every rank would compute the whole run alone and write the same files.
        std::cerr << fmt::format("fortu: error: started by mpirun, but MPI is not available: {}\n", error);
        std::exit(1);
    }
    mpi_ = mpi;
}

World::~World() {
    if (mpi_) mpi_->finalize();
}

void World::barrier() {
    if (mpi_) mpi_->barrier();
}

void World::abort(int status) {
    if (mpi_) mpi_->abort(status);
    std::exit(status);
}

std::vector<double> World::gather(const std::vector<double>& values) {
    if (!mpi_) return values;
    std::vector<double> all(rank_ == 0 ? values.size() * size_ : 0);
    mpi_->gather(values.data(), int(values.size()), all.data());
    return all;
}

World::Counter::Counter(World& world) : world_(world) {
    if (world.mpi_) shared_ = world.mpi_->counter_create();
}

World::Counter::~Counter() {
    if (shared_) world_.mpi_->counter_free(shared_);
}

std::uint64_t World::Counter::next() {
    std::lock_guard lock(world_.mpi_mutex());
    return shared_ ? world_.mpi_->counter_next(shared_) : local_++;
}

}  // namespace fortu
