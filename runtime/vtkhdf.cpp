// runtime/vtkhdf.cpp — the VTKHDF ImageData brick writer (vtkhdf.hpp); its HDF5 calls are in
// the plug-in libfortu_hdf5.so (vtkhdf_module.hpp), loaded by the first run that writes one.
//
// HDF5 is not thread-safe (Debian builds it without the thread-safe option) and, under
// mpirun, calls MPI: every call holds one lock, the caller's MPI lock when it gives one.
// Durability for the done map: an fdatasync of the file's own descriptor puts every brick
// written so far on disk (vtkhdf_module.cpp says why that is enough).
#include "runtime/vtkhdf.hpp"

#include "runtime/brick_files.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output_error.hpp"
#include "runtime/plugin_loader.hpp"
#include "runtime/volume_order.hpp"
#include "runtime/vtkhdf_module.hpp"

#include <array>
#include <cstdint>
#include <fcntl.h>
#include <fmt/format.h>
#include <mutex>
#include <unistd.h>
#include <utility>

#ifndef FORTU_HDF5_MODULE_BUILD_PATH
#define FORTU_HDF5_MODULE_BUILD_PATH ""
#endif

namespace fortu {
namespace {

const VtkHdfModule* hdf5_module(std::string& error) {
    static LazyPlugin plugin({"libfortu_hdf5.so", "FORTU_HDF5_MODULE", FORTU_HDF5_MODULE_BUILD_PATH,
                              "fortu_hdf5_module",
                              "(fortu builds it next to its binary when HDF5 is installed: apt-get install "
                              "libhdf5-openmpi-dev, then rebuild): .hdf/.vtkhdf is not available",
                              kVtkHdfModuleVersion});
    return static_cast<const VtkHdfModule*>(plugin.get(error));
}

class VtkHdfBricks final : public BrickOutput {
public:
    explicit VtkHdfBricks(const BrickOutputSpec& spec)
        : spec_(spec), partial_(partial_path(spec.path)), arrays_(array_names(spec)) {
        std::string error;
        module_ = hdf5_module(error);
        if (!module_) throw OutputError(spec.path, error);
        const Grid& g = spec.layout.grid;
        VtkHdfLayout layout{partial_, spec.create, spec.collective,
                            {std::uint64_t(g.slices()), std::uint64_t(g.rows()), std::uint64_t(g.cols())},
                            volume_origin(g), volume_spacing(g), arrays_};
        file_ = module_->open(layout, error);
        if (!file_) fail(error);
        fd_ = ::open(partial_.c_str(), O_RDWR | O_CLOEXEC);
        if (fd_ < 0) {
            module_->close(std::exchange(file_, nullptr));
            fail("cannot open the file to sync it");
        }
    }

    ~VtkHdfBricks() override {
        if (fd_ >= 0) ::close(fd_);
        if (file_) module_->close(file_);   // after an error: its own error is already reported
    }

    void write(std::size_t, const BrickBox& box, const std::vector<double>& values,
               std::span<const double> components) override {
        std::unique_lock lock = hold();
        write_array(box, 0, values.data());
        for (std::size_t k = 1; k < arrays_.size(); ++k)
            write_array(box, k, components.data() + (k - 1) * box.points());
    }

    void sync() override {
        if (::fdatasync(fd_) != 0) fail("cannot sync the file");
    }

    void close() override {
        std::unique_lock lock = hold();
        void* file = std::exchange(file_, nullptr);
        if (std::string error = file ? module_->close(file) : ""; !error.empty()) fail(error);
    }

    void finish(std::size_t) override {
        PartialFile file(partial_, spec_.path, /*keep=*/true);
        file.commit();   // fsync, rename over the destination
    }

private:
    /// The point data: the value, then with M-images the components n1...
    static std::vector<std::string> array_names(const BrickOutputSpec& spec) {
        std::vector<std::string> names{"value"};
        if (spec.mimages)
            for (int k = 1; k <= fv_component_count(spec.layout.grid); ++k) names.push_back(fmt::format("n{}", k));
        return names;
    }

    /// One array's part of a brick (BrickBox::local order) to its hyperslabs; the lock held.
    void write_array(const BrickBox& box, std::size_t array, const double* values) {
        const Grid& g = spec_.layout.grid;
        const std::array<int, 3> e = box.extent();
        // One slice at a time, its rows in volume order (Y from the smallest).
        staging_.resize(std::size_t(e[0]) * e[1]);
        const std::array<std::uint64_t, 3> count{1, std::uint64_t(e[1]), std::uint64_t(e[0])};
        for (int s = box.lo[2]; s <= box.hi[2]; ++s) {
            for (int r = box.hi[1], row = 0; r >= box.lo[1]; --r, ++row)
                std::copy_n(values + box.local(box.lo[0], r, s), e[0], staging_.data() + std::size_t(row) * e[0]);
            const std::array<std::uint64_t, 3> start{std::uint64_t(s), std::uint64_t(g.rows() - 1 - box.hi[1]),
                                                     std::uint64_t(box.lo[0])};
            if (std::string error = module_->write(file_, array, start, count, staging_.data()); !error.empty())
                fail(error);
        }
    }

    std::unique_lock<std::mutex> hold() { return std::unique_lock(spec_.mpi_mutex ? *spec_.mpi_mutex : mutex_); }

    [[noreturn]] void fail(const std::string& what) const { throw OutputError(spec_.path, "HDF5: " + what); }

    BrickOutputSpec spec_;
    std::string partial_;
    std::vector<std::string> arrays_;
    const VtkHdfModule* module_ = nullptr;
    void* file_ = nullptr;
    int fd_ = -1;
    std::mutex mutex_;
    std::vector<double> staging_;
};

}  // namespace

std::unique_ptr<BrickOutput> open_vtkhdf_bricks(const BrickOutputSpec& spec) {
    return std::make_unique<VtkHdfBricks>(spec);
}

}  // namespace fortu
