// runtime/vdb.hpp — a field as an OpenVDB FloatGrid (a 2D one as one slice) (.vdb), sparse: only the narrow band
// of nodes with |value| ≤ band × cell is stored (active voxels); elsewhere inactive tiles
// carry ±band × cell with the side's sign (positive inside, fortu's convention, the opposite
// of OpenVDB's level sets). The transform maps voxel (i, j, k) to the grid's node: origin +
// (i, j, k) × spacing. Written by the plug-in libfortu_vdb.so (OpenVDB, libopenvdb-dev),
// loaded only by runs that write a .vdb; a build without OpenVDB refuses the format.
#pragma once

#include "runtime/field.hpp"
#include "runtime/output_formats.hpp"

#include <string>

namespace fortu {

/// The plug-in's interface (vdb_module.cpp).
struct VdbModule {
    int version;
    /// Encodes `field` as the bytes of a .vdb file into `bytes`; "" or the reason it failed.
    /// Bytes, not a file: OpenVDB's own file writer ignores write errors (a full disk would
    /// leave a truncated file), so the caller writes them through the checked write path.
    std::string (*encode)(const Field& field, double band_cells, std::string& bytes);
};
inline constexpr int kVdbModuleVersion = 2;

/// Writes the .vdb through the plug-in, atomically. Throws OutputError.
void write_vdb(const Field& field, const OutputTarget& target, const OutputOptions& options);

}  // namespace fortu
