// runtime/vtkhdf_module.cpp — the HDF5 plug-in, libfortu_hdf5.so (vtkhdf_module.hpp): a
// VTKHDF ImageData file on the HDF5 C API, made, reopened, written by hyperslabs and closed.
//
// Durability for the caller's done map: HDF5 keeps no raw data in memory (no sieve buffer)
// and the dataset's metadata never changes after creation, so an fdatasync of the file's own
// descriptor (vtkhdf.cpp) puts every brick written so far on disk, on any rank.
#include "runtime/vtkhdf_module.hpp"

#include <hdf5.h>

#include <memory>
#include <stdexcept>

namespace fortu {
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

struct Failure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

void check(const Id& id, const std::string& what) {
    if (!id.valid()) throw Failure(what);
}

class VtkHdfFile {
public:
    explicit VtkHdfFile(const VtkHdfLayout& layout) : layout_(layout) {
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);   // errors become our messages, not HDF5's stack dumps
        Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
        H5Pset_sieve_buf_size(fapl.get(), 0);           // raw data straight to the file (durability)
        if (layout.collective) {
#ifdef H5_HAVE_PARALLEL
            H5Pset_fapl_mpio(fapl.get(), MPI_COMM_WORLD, MPI_INFO_NULL);
#else
            throw Failure("this fortu's HDF5 is serial: ranks under mpirun cannot share one .hdf "
                          "(install libhdf5-openmpi-dev and rebuild)");
#endif
        }
        if (layout.create) {
            file_ = Id(H5Fcreate(layout.path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose);
            check(file_, "cannot create the file");
            make_structure();
        } else {
            file_ = Id(H5Fopen(layout.path.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose);
            check(file_, "cannot reopen the unfinished file to resume");
            for (const std::string& name : layout.arrays) {
                const std::string path = "/VTKHDF/PointData/" + name;
                datasets_.emplace_back(H5Dopen2(file_.get(), path.c_str(), H5P_DEFAULT), H5Dclose);
                check(datasets_.back(), "the unfinished file has no " + path);
            }
        }
        if (H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) throw Failure("cannot flush the file's structure");
        transfer_ = Id(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
#ifdef H5_HAVE_PARALLEL
        // Independent: ranks draw different numbers of bricks, so writes cannot be matched.
        if (layout.collective) H5Pset_dxpl_mpio(transfer_.get(), H5FD_MPIO_INDEPENDENT);
#endif
    }

    std::string write(std::size_t array, const std::array<std::uint64_t, 3>& start,
                      const std::array<std::uint64_t, 3>& count, const double* values) {
        const hsize_t points = hsize_t(count[0]) * count[1] * count[2];
        const hsize_t file_start[3] = {start[0], start[1], start[2]};
        const hsize_t file_count[3] = {count[0], count[1], count[2]};
        Id memory(H5Screate_simple(1, &points, nullptr), H5Sclose);
        Id file_space(H5Dget_space(datasets_.at(array).get()), H5Sclose);
        if (!memory.valid() || !file_space.valid() ||
            H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, file_start, nullptr, file_count, nullptr) < 0 ||
            H5Dwrite(datasets_[array].get(), H5T_NATIVE_DOUBLE, memory.get(), file_space.get(), transfer_.get(),
                     values) < 0)
            return "cannot write a brick's values";
        return "";
    }

    std::string close() {
        transfer_.reset();
        bool ok = true;
        for (Id& dataset : datasets_) ok = dataset.reset() && ok;   // collective under mpirun
        return file_.reset() && ok ? "" : "cannot close the file";
    }

private:
    void attribute(hid_t on, const char* name, hid_t type, const void* data, hsize_t count) {
        Id space(count ? H5Screate_simple(1, &count, nullptr) : H5Screate(H5S_SCALAR), H5Sclose);
        Id a(H5Acreate2(on, name, type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
        if (!a.valid() || H5Awrite(a.get(), type, data) < 0)
            throw Failure(std::string("cannot write the attribute ") + name);
    }

    void text_attribute(hid_t on, const char* name, const std::string& text) {
        Id type(H5Tcopy(H5T_C_S1), H5Tclose);
        H5Tset_size(type.get(), text.size());
        H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
        H5Tset_cset(type.get(), H5T_CSET_ASCII);
        attribute(on, name, type.get(), text.data(), 0);
    }

    void make_structure() {
        Id root(H5Gcreate2(file_.get(), "VTKHDF", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        check(root, "cannot create the group /VTKHDF");
        const std::int64_t version[2] = {1, 0};
        attribute(root.get(), "Version", H5T_STD_I64LE, version, 2);
        text_attribute(root.get(), "Type", "ImageData");
        const std::array<std::uint64_t, 3>& d = layout_.dims;
        const std::int64_t extent[6] = {0, std::int64_t(d[2]) - 1, 0, std::int64_t(d[1]) - 1, 0, std::int64_t(d[0]) - 1};
        attribute(root.get(), "WholeExtent", H5T_STD_I64LE, extent, 6);
        attribute(root.get(), "Origin", H5T_IEEE_F64LE, layout_.origin.data(), 3);
        attribute(root.get(), "Spacing", H5T_IEEE_F64LE, layout_.spacing.data(), 3);
        const double direction[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        attribute(root.get(), "Direction", H5T_IEEE_F64LE, direction, 9);
        Id point_data(H5Gcreate2(root.get(), "PointData", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        check(point_data, "cannot create the group /VTKHDF/PointData");
        text_attribute(point_data.get(), "Scalars", layout_.arrays.front());
        const hsize_t dims[3] = {d[0], d[1], d[2]};
        Id space(H5Screate_simple(3, dims, nullptr), H5Sclose);
        Id create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
        H5Pset_layout(create.get(), H5D_CONTIGUOUS);
        H5Pset_alloc_time(create.get(), H5D_ALLOC_TIME_EARLY);   // all space now: writes touch no metadata
        H5Pset_fill_time(create.get(), H5D_FILL_TIME_NEVER);     // every value is written by a brick
        H5Pset_obj_track_times(create.get(), false);
        for (const std::string& name : layout_.arrays) {
            datasets_.emplace_back(H5Dcreate2(point_data.get(), name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                                              create.get(), H5P_DEFAULT),
                                   H5Dclose);
            check(datasets_.back(), "cannot create the dataset /VTKHDF/PointData/" + name);
        }
    }

    VtkHdfLayout layout_;
    Id file_, transfer_;
    std::vector<Id> datasets_;   ///< layout_.arrays, in order
};

void* open(const VtkHdfLayout& layout, std::string& error) {
    try {
        return new VtkHdfFile(layout);
    } catch (const std::exception& e) {
        error = e.what();
        return nullptr;
    }
}

std::string write(void* file, std::size_t array, const std::array<std::uint64_t, 3>& start,
                  const std::array<std::uint64_t, 3>& count, const double* values) {
    return static_cast<VtkHdfFile*>(file)->write(array, start, count, values);
}

std::string close(void* file) {
    std::unique_ptr<VtkHdfFile> owned(static_cast<VtkHdfFile*>(file));
    return owned->close();
}

constexpr VtkHdfModule kModule{kVtkHdfModuleVersion, &open, &write, &close};

}  // namespace
}  // namespace fortu

extern "C" void* fortu_hdf5_module() { return const_cast<fortu::VtkHdfModule*>(&fortu::kModule); }
