// runtime/mesh_compare.hpp — what the golden runner compares between two meshes: topology
// (closed and manifold, genus, triangle count within a tolerance) and geometry (the
// symmetric Hausdorff distance, sampled at vertices and triangle centres).
//
// Why not byte equality: a mesh is a faithful answer up to where its vertices land; a change
// to the mesher that moves vertices by round-off or adds a few triangles is not a regression,
// one that opens a hole, changes the genus or moves the surface is.
#pragma once

#include "runtime/mesh.hpp"
#include "runtime/output_formats.hpp"

#include <array>
#include <cstddef>
#include <string>

namespace fortu {

/// Every edge in exactly two triangles, traversed once in each direction (closed, manifold,
/// consistently oriented); the Euler characteristic gives the genus.
struct MeshTopology {
    std::size_t vertices = 0, edges = 0, triangles = 0;
    std::size_t boundary_edges = 0;       ///< in one triangle only
    std::size_t nonmanifold_edges = 0;    ///< in three or more
    std::size_t misoriented_edges = 0;    ///< two triangles traverse it the same way
    std::size_t components = 0;
    long genus = 0;                       ///< sum over components, from V − E + F = 2C − 2g
    bool closed_manifold() const { return boundary_edges == 0 && nonmanifold_edges == 0 && misoriented_edges == 0; }
};

MeshTopology mesh_topology(const Mesh& mesh);

/// The point of triangle abc nearest p.
std::array<double, 3> closest_point_on_triangle(const std::array<double, 3>& p, const std::array<double, 3>& a,
                                                const std::array<double, 3>& b, const std::array<double, 3>& c);

/// Distance from p to triangle abc.
double point_triangle_distance(const std::array<double, 3>& p, const std::array<double, 3>& a,
                               const std::array<double, 3>& b, const std::array<double, 3>& c);

/// The largest distance from a point of either mesh (vertices and triangle centres) to the
/// other mesh's triangles.
double hausdorff_distance(const Mesh& a, const Mesh& b);

/// The golden comparator of the mesh rows: reads both files (mesh_io.hpp); they differ when
/// either is not closed and manifold, the genus differs, the triangle counts differ by more
/// than 2%, or the Hausdorff distance exceeds the tolerance.
OutputComparison compare_mesh_output(const ComparedOutput& compared);

}  // namespace fortu
