// runtime/vtkhdf.cpp — the VTKHDF ImageData brick writer (vtkhdf.hpp) on the HDF5 C API.
//
// HDF5 is not thread-safe (Debian builds it without the thread-safe option) and, under
// mpirun, calls MPI: every call holds one lock, the caller's MPI lock when it gives one.
// Durability for the done map: HDF5 keeps no raw data in memory (no sieve buffer) and the
// dataset's metadata never changes after creation, so an fdatasync of the file's own
// descriptor puts every brick written so far on disk, on any rank, without a collective.
#include "runtime/vtkhdf.hpp"

#include "runtime/brick_files.hpp"
#include "runtime/fv_model.hpp"
#include "runtime/output_error.hpp"
#include "runtime/volume_order.hpp"

#include <array>
#include <cstdint>
#include <fcntl.h>
#include <fmt/format.h>
#include <mutex>
#include <optional>
#include <unistd.h>

#ifdef FORTU_HAVE_HDF5
#include <hdf5.h>
#endif

namespace fortu {

#ifdef FORTU_HAVE_HDF5
namespace {

/// An HDF5 identifier closed by its own close function.
class Id {
public:
    Id() = default;
    Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
    Id(Id&& other) noexcept : id_(other.id_), close_(other.close_) { other.id_ = -1; }
    Id& operator=(Id&& other) noexcept {
        std::swap(id_, other.id_);
        std::swap(close_, other.close_);
        return *this;
    }
    ~Id() { reset(); }
    /// Closes now; false when HDF5 reports an error (a collective close that failed).
    bool reset() {
        const bool ok = id_ < 0 || close_(id_) >= 0;
        id_ = -1;
        return ok;
    }
    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }

private:
    hid_t id_ = -1;
    herr_t (*close_)(hid_t) = nullptr;
};

class VtkHdfBricks final : public BrickOutput {
public:
    explicit VtkHdfBricks(const BrickOutputSpec& spec) : spec_(spec), partial_(partial_path(spec.path)) {
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);   // errors become our messages, not HDF5's stack dumps
        Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
        H5Pset_sieve_buf_size(fapl.get(), 0);           // raw data straight to the file (durability)
        if (spec.collective) {
#ifdef H5_HAVE_PARALLEL
            H5Pset_fapl_mpio(fapl.get(), MPI_COMM_WORLD, MPI_INFO_NULL);
#else
            throw OutputError(spec.path, "this fortu's HDF5 is serial: ranks under mpirun cannot share one .hdf "
                                         "(install libhdf5-openmpi-dev and rebuild)");
#endif
        }
        const Grid& g = spec.layout.grid;
        if (spec.create) {
            file_ = Id(H5Fcreate(partial_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose);
            check(file_, "cannot create the file");
            make_structure(g);
        } else {
            file_ = Id(H5Fopen(partial_.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose);
            check(file_, "cannot reopen the unfinished file to resume");
            for (const std::string& name : array_names()) {
                const std::string path = "/VTKHDF/PointData/" + name;
                datasets_.emplace_back(H5Dopen2(file_.get(), path.c_str(), H5P_DEFAULT), H5Dclose);
                check(datasets_.back(), "the unfinished file has no " + path);
            }
        }
        if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) fail("cannot flush the file's structure");
        transfer_ = Id(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
#ifdef H5_HAVE_PARALLEL
        // Independent: ranks draw different numbers of bricks, so writes cannot be matched.
        if (spec.collective) H5Pset_dxpl_mpio(transfer_.get(), H5FD_MPIO_INDEPENDENT);
#endif
        fd_ = ::open(partial_.c_str(), O_RDWR | O_CLOEXEC);
        if (fd_ < 0) fail("cannot open the file to sync it");
    }

    ~VtkHdfBricks() override {
        if (fd_ >= 0) ::close(fd_);
    }

    void write(std::size_t, const BrickBox& box, const std::vector<double>& values,
               std::span<const double> components) override {
        std::unique_lock lock = hold();
        write_array(box, datasets_[0], values.data());
        for (std::size_t k = 1; k < datasets_.size(); ++k)
            write_array(box, datasets_[k], components.data() + (k - 1) * box.points());
    }

    void sync() override {
        if (::fdatasync(fd_) != 0) fail("cannot sync the file");
    }

    void close() override {
        std::unique_lock lock = hold();
        transfer_.reset();
        bool ok = true;
        for (Id& dataset : datasets_) ok = dataset.reset() && ok;   // collective under mpirun
        if (!(file_.reset() && ok)) fail("cannot close the file");
    }

    void finish(std::size_t) override {
        PartialFile file(partial_, spec_.path, /*keep=*/true);
        file.commit();   // fsync, rename over the destination
    }

private:
    /// The point data: the value, then with M-images the components n1...
    std::vector<std::string> array_names() const {
        std::vector<std::string> names{"value"};
        if (spec_.mimages)
            for (int k = 1; k <= fv_component_count(spec_.layout.grid); ++k) names.push_back(fmt::format("n{}", k));
        return names;
    }

    /// One array's part of a brick (BrickBox::local order) to its hyperslabs; the lock held.
    void write_array(const BrickBox& box, const Id& dataset, const double* values) {
        const Grid& g = spec_.layout.grid;
        const std::array<int, 3> e = box.extent();
        // One slice at a time, its rows in volume order (Y from the smallest).
        staging_.resize(std::size_t(e[0]) * e[1]);
        const hsize_t count[3] = {1, hsize_t(e[1]), hsize_t(e[0])};
        const hsize_t points = hsize_t(e[0]) * e[1];
        Id memory(H5Screate_simple(1, &points, nullptr), H5Sclose);
        Id file_space(H5Dget_space(dataset.get()), H5Sclose);
        for (int s = box.lo[2]; s <= box.hi[2]; ++s) {
            for (int r = box.hi[1], row = 0; r >= box.lo[1]; --r, ++row)
                std::copy_n(values + box.local(box.lo[0], r, s), e[0], staging_.data() + std::size_t(row) * e[0]);
            const hsize_t start[3] = {hsize_t(s), hsize_t(g.rows() - 1 - box.hi[1]), hsize_t(box.lo[0])};
            if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) < 0 ||
                H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, memory.get(), file_space.get(), transfer_.get(),
                         staging_.data()) < 0)
                fail("cannot write a brick's values");
        }
    }

    std::unique_lock<std::mutex> hold() { return std::unique_lock(spec_.mpi_mutex ? *spec_.mpi_mutex : mutex_); }

    [[noreturn]] void fail(const std::string& what) const { throw OutputError(spec_.path, "HDF5: " + what); }
    void check(const Id& id, const std::string& what) const {
        if (!id.valid()) fail(what);
    }

    void attribute(hid_t on, const char* name, hid_t type, const void* data, hsize_t count) {
        Id space(count ? H5Screate_simple(1, &count, nullptr) : H5Screate(H5S_SCALAR), H5Sclose);
        Id a(H5Acreate2(on, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
        if (!a.valid() || H5Awrite(a.get(), type, data) < 0) fail(std::string("cannot write the attribute ") + name);
    }

    void text_attribute(hid_t on, const char* name, const std::string& text) {
        Id type(H5Tcopy(H5T_C_S1), H5Tclose);
        H5Tset_size(type.get(), text.size());
        H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
        H5Tset_cset(type.get(), H5T_CSET_ASCII);
        attribute(on, name, type.get(), text.data(), 0);
    }

    void make_structure(const Grid& g) {
        Id root(H5Gcreate2(file_.get(), "VTKHDF", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        check(root, "cannot create the group /VTKHDF");
        const std::int64_t version[2] = {1, 0};
        attribute(root.get(), "Version", H5T_STD_I64LE, version, 2);
        text_attribute(root.get(), "Type", "ImageData");
        const std::int64_t extent[6] = {0, g.cols() - 1, 0, g.rows() - 1, 0, g.slices() - 1};
        attribute(root.get(), "WholeExtent", H5T_STD_I64LE, extent, 6);
        const std::array<double, 3> origin = volume_origin(g), spacing = volume_spacing(g);
        attribute(root.get(), "Origin", H5T_IEEE_F64LE, origin.data(), 3);
        attribute(root.get(), "Spacing", H5T_IEEE_F64LE, spacing.data(), 3);
        const double direction[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        attribute(root.get(), "Direction", H5T_IEEE_F64LE, direction, 9);
        Id point_data(H5Gcreate2(root.get(), "PointData", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        check(point_data, "cannot create the group /VTKHDF/PointData");
        text_attribute(point_data.get(), "Scalars", "value");
        const hsize_t dims[3] = {hsize_t(g.slices()), hsize_t(g.rows()), hsize_t(g.cols())};
        Id space(H5Screate_simple(3, dims, nullptr), H5Sclose);
        Id create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
        H5Pset_layout(create.get(), H5D_CONTIGUOUS);
        H5Pset_alloc_time(create.get(), H5D_ALLOC_TIME_EARLY);   // all space now: writes touch no metadata
        H5Pset_fill_time(create.get(), H5D_FILL_TIME_NEVER);     // every value is written by a brick
        H5Pset_obj_track_times(create.get(), false);
        for (const std::string& name : array_names()) {
            datasets_.emplace_back(H5Dcreate2(point_data.get(), name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                                              create.get(), H5P_DEFAULT),
                                   H5Dclose);
            check(datasets_.back(), "cannot create the dataset /VTKHDF/PointData/" + name);
        }
    }

    BrickOutputSpec spec_;
    std::string partial_;
    Id file_, transfer_;
    std::vector<Id> datasets_;   ///< array_names(), in order
    int fd_ = -1;
    std::mutex mutex_;
    std::vector<double> staging_;
};

}  // namespace

std::unique_ptr<BrickOutput> open_vtkhdf_bricks(const BrickOutputSpec& spec) {
    return std::make_unique<VtkHdfBricks>(spec);
}

#else

std::unique_ptr<BrickOutput> open_vtkhdf_bricks(const BrickOutputSpec& spec) {
    throw OutputError(spec.path, "fortu was built without HDF5: .hdf/.vtkhdf is not available "
                                 "(apt-get install libhdf5-openmpi-dev, then rebuild)");
}

#endif

}  // namespace fortu
