// runtime/brick_output.hpp — volume outputs written brick by brick (.vti, .vdb), durably, so
// memory is bounded by the bricks in flight and a killed run resumes (brick_files.hpp).
//
// Why each format's own means: a .vti is one dense array, so bricks go to their offsets of
// the final file (a partial file with holes, renamed when complete); a .pvti is the same
// cut into pieces by slabs of slices (each piece's extent includes the first plane of the
// next, as VTK requires), one .vti each, and the index naming them; a .vdb is a sparse
// tree, so each brick's narrow-band voxels are appended to a record file per writer (one
// per MPI rank), and the tree is built from all of them once at the end, the same way the
// in-memory writer builds it, so both files hold the same values.
#pragma once

#include "runtime/bricks.hpp"
#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/grid.hpp"

#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace fortu {

struct BrickOutputSpec {
    std::string path;          ///< the destination (-o)
    BrickLayout layout;        ///< the grid and its bricks (brick_layout())
    double vdb_band = 3.0;     ///< --band, in cells
    int part = 0;              ///< this writer's number (MPI rank)
    bool create = true;        ///< start the partial files afresh (false: resume, or a rank joining rank 0's file)
    int pieces = 1;            ///< a .pvti's pieces (at most the layers of bricks along Z)
    bool collective = false;   ///< every MPI rank opens and closes the one file together (.hdf)
    std::mutex* mpi_mutex = nullptr;   ///< held by writers that call MPI (one thread at a time)
    bool mimages = false;      ///< also the FV model's components n1.. (--mimages; .vti, .pvti, .hdf)
};

class BrickOutput {
public:
    virtual ~BrickOutput() = default;
    /// Values beyond ±this are not needed (a sparse format's band); nullopt: every value.
    virtual std::optional<double> skip_beyond() const { return std::nullopt; }
    /// Writes one brick's values (BrickBox::local order) and, for spec.mimages, its components:
    /// n_k of local node i at components[(k - 1) * box.points() + i]. Thread-safe.
    virtual void write(std::size_t index, const BrickBox& box, const std::vector<double>& values,
                       std::span<const double> components) = 0;
    /// Puts every brick written so far on disk (fdatasync). Thread-safe.
    virtual void sync() = 0;
    /// Ends this process's writing, on every rank (collective where the format is).
    virtual void close() {}
    /// Assembles the destination from the partial files of every writer (call once, when
    /// every brick of every part is written; `memory_limit` bounds what assembling may hold,
    /// 0: no bound).
    virtual void finish(std::size_t memory_limit) = 0;
};

/// True for the extensions written brick by brick (.vti, .pvti, .vdb).
bool brick_output_supported(const std::string& path);
/// True for those written only brick by brick (.pvti, .hdf, .vtkhdf): every 3D run to
/// them is bricked.
bool brick_output_only(const std::string& path);

/// The bricks of a run writing `path` with --brick `edge`: whole rows for dense files,
/// so each brick is a few long writes; cubes for the sparse .vdb.
BrickLayout brick_layout(const std::string& path, const Grid& grid, int edge);

/// True when every rank opens the file at once (brick_output_collective), not rank 0 first.
bool brick_output_collective(const std::string& path);

/// True for the brick formats that also hold the M-images' components (.vti, .pvti, .hdf,
/// .vtkhdf): dense arrays of point data beside the value. A .vdb keeps a narrow band of one
/// float grid, so it does not.
bool brick_output_takes_mimages(const std::string& path);

/// Whether the partial files of an unfinished run of `spec` are there to resume.
bool brick_partials_exist(const BrickOutputSpec& spec);

/// The writer for `spec.path`. Throws OutputError.
std::unique_ptr<BrickOutput> open_brick_output(const BrickOutputSpec& spec);

/// A field held in memory (a 2D run, a --slice) written by the brick writer as one brick
/// (options.mimages: with its components): the output table's writer of the formats written
/// only in bricks.
void write_field_as_brick(const Field& field, const OutputTarget& target, const OutputOptions& options);

}  // namespace fortu
