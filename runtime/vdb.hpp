// runtime/vdb.hpp — a field as an OpenVDB FloatGrid (a 2D one as one slice) (.vdb), sparse: only the narrow band
// of nodes with |value| ≤ band × cell is stored (active voxels); elsewhere inactive tiles
// carry ±band × cell with the side's sign (positive inside, fortu's convention, the opposite
// of OpenVDB's level sets). The transform maps voxel (i, j, k) to the grid's node: origin +
// (i, j, k) × spacing. Written by the plug-in libfortu_vdb.so (OpenVDB, libopenvdb-dev),
// loaded only by runs that write a .vdb; a build without OpenVDB refuses the format.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/volume_order.hpp"

#include <algorithm>

#include <cstddef>
#include <cstdint>
#include <string>

namespace fortu {

/// The plug-in's interface (vdb_module.cpp).
struct VdbModule {
    int version;
    /// Encodes `field` as the bytes of a .vdb file into `bytes`; "" or the reason it failed.
    /// Bytes, not a file: OpenVDB's own file writer ignores write errors (a full disk would
    /// leave a truncated file), so the caller writes them through the checked write path.
    std::string (*encode)(const Field& field, double band_cells, std::string& bytes);
    /// The same grid built voxel by voxel (bricked runs, brick_output.hpp): begin() for the
    /// field's grid (its values unused), add() the active voxels (volume-order indices,
    /// values already within the band), finish() flood-fills, encodes and frees the
    /// builder; discard() frees it. memory(): bytes the tree holds so far.
    void* (*begin)(const Grid& grid, double band_cells);
    void (*add)(void* builder, const std::int32_t* ijk, const float* values, std::size_t count);
    std::string (*finish)(void* builder, std::string& bytes);
    void (*discard)(void* builder);
    std::size_t (*memory)(void* builder);
};
inline constexpr int kVdbModuleVersion = 3;

/// The plug-in, loaded on first use; nullptr with the reason in `error`.
const VdbModule* vdb_module(std::string& error);

/// The narrow band's half width in world units for `band_cells` cells of `grid`: nodes with
/// |value| <= it are stored.
inline double vdb_band_width(const Grid& grid, double band_cells) {
    const std::array<double, 3> spacing = volume_spacing(grid);
    return band_cells * std::min({spacing[0], spacing[1], spacing[2]});
}

/// Writes the .vdb through the plug-in, atomically. Throws OutputError.
void write_vdb(const Field& field, const OutputTarget& target, const OutputOptions& options);

}  // namespace fortu
