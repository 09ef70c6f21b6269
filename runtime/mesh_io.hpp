// runtime/mesh_io.hpp — the mesh formats of the output-format table (output_formats.cpp):
// STL (binary, or ASCII with --ascii), Wavefront OBJ with normals, binary PLY; and their
// readers, for the golden runner's mesh comparator (mesh_compare.hpp).
//
// Why these three: every mesh tool reads STL (float32, one record per triangle, no sharing),
// OBJ keeps the shared vertices and the exact normals as text, PLY keeps them as binary
// float64, so a PLY is the mesh exactly as computed.
#pragma once

#include "runtime/mesh.hpp"
#include "runtime/output_options.hpp"

#include <string>

namespace fortu {

/// Each writes `path` atomically (write_file_atomically); throws OutputError.
void write_stl(const Mesh& mesh, const std::string& path, const OutputOptions& options);
void write_obj(const Mesh& mesh, const std::string& path, const OutputOptions& options);
void write_ply(const Mesh& mesh, const std::string& path, const OutputOptions& options);

/// Reads a mesh fortu wrote (STL binary or ASCII, OBJ, binary PLY), by the path's extension;
/// STL vertices are welded by position. Throws OutputError for a file it cannot read.
Mesh read_mesh(const std::string& path);

}  // namespace fortu
