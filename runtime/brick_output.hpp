// runtime/brick_output.hpp — volume outputs written brick by brick (.vti, .vdb), durably, so
// memory is bounded by the bricks in flight and a killed run resumes (brick_files.hpp).
//
// Why each format's own means: a .vti is one dense array, so bricks go to their offsets of
// the final file (a partial file with holes, renamed when complete); a .vdb is a sparse
// tree, so each brick's narrow-band voxels are appended to a record file per writer (one
// per MPI rank), and the tree is built from all of them once at the end, the same way the
// in-memory writer builds it, so both files hold the same values.
#pragma once

#include "runtime/bricks.hpp"
#include "runtime/grid.hpp"

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fortu {

struct BrickOutputSpec {
    std::string path;          ///< the destination (-o)
    Grid grid;
    double vdb_band = 3.0;     ///< --band, in cells
    int part = 0;              ///< this writer's number (MPI rank)
    bool create = true;        ///< start the partial files afresh (false: resume, or a rank joining rank 0's file)
};

class BrickOutput {
public:
    virtual ~BrickOutput() = default;
    /// Values beyond ±this are not needed (a sparse format's band); nullopt: every value.
    virtual std::optional<double> skip_beyond() const { return std::nullopt; }
    /// Writes one brick's values (BrickBox::local order) durably. Thread-safe.
    virtual void write(std::size_t index, const BrickBox& box, const std::vector<double>& values) = 0;
    /// Assembles the destination from the partial files of every writer (call once, when
    /// every brick of every part is written; `memory_limit` bounds what assembling may hold,
    /// 0: no bound).
    virtual void finish(std::size_t memory_limit) = 0;
};

/// True for the extensions written brick by brick (.vti, .vdb).
bool brick_output_supported(const std::string& path);

/// The writer for `spec.path`. Throws OutputError.
std::unique_ptr<BrickOutput> open_brick_output(const BrickOutputSpec& spec);

}  // namespace fortu
