// runtime/vtkhdf_module.hpp — the table the HDF5 plug-in, libfortu_hdf5.so
// (vtkhdf_module.cpp), gives the VTKHDF brick writer (vtkhdf.cpp).
//
// Why a plug-in: Debian's HDF5 pulls in libcurl, GnuTLS, OpenSSL, Kerberos, LDAP and Open MPI;
// linked into the binary they were mapped and relocated by every run (plugin_loader.hpp). The
// table holds only the HDF5 calls; the file's naming, locking, syncing and commit stay in
// vtkhdf.cpp. Errors cross as text (the caller throws OutputError with it).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fortu {

/// What the file holds: an ImageData of `dims` nodes (slices, rows, columns: the datasets'
/// order), its point data `arrays` (Float64; the first is the Scalars).
struct VtkHdfLayout {
    std::string path;                          ///< the file to create, or to reopen to resume
    bool create = true;
    bool collective = false;                   ///< every rank of MPI_COMM_WORLD opens it (MPI-IO)
    std::array<std::uint64_t, 3> dims{};       ///< slices, rows, columns
    std::array<double, 3> origin{}, spacing{}; ///< x, y, z
    std::vector<std::string> arrays;
};

struct VtkHdfModule {
    int version;
    /// The open file, or nullptr with the reason in `error`.
    void* (*open)(const VtkHdfLayout& layout, std::string& error);
    /// `values` (count's slices × rows × columns, columns fastest) into array `array` at
    /// `start` (slice, row, column); "" or the reason it failed. Not thread-safe.
    std::string (*write)(void* file, std::size_t array, const std::array<std::uint64_t, 3>& start,
                         const std::array<std::uint64_t, 3>& count, const double* values);
    /// Closes the datasets and the file (collective under mpirun) and frees `file`; "" or the
    /// reason it failed.
    std::string (*close)(void* file);
};
inline constexpr int kVtkHdfModuleVersion = 1;

}  // namespace fortu
