// runtime/mesh.hpp — a triangle mesh of a model's zero surface (the mesher, interp/mesher.hpp,
// makes it; the mesh writers, mesh_io.hpp, write it). Indexed: each vertex once, with the
// outward unit normal of the surface there.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace fortu {

struct Mesh {
    std::vector<std::array<double, 3>> vertices;
    std::vector<std::array<double, 3>> normals;          ///< per vertex, unit, outward (may be empty)
    std::vector<std::array<uint32_t, 3>> triangles;      ///< counter-clockwise seen from outside
};

/// Drops the vertices no triangle uses, keeping the others in their order, and renumbers the
/// triangles. Returns each old vertex's new number, UINT32_MAX where it was dropped.
inline std::vector<uint32_t> drop_unused_vertices(Mesh& mesh) {
    std::vector<uint32_t> renumber(mesh.vertices.size(), UINT32_MAX);
    for (const auto& t : mesh.triangles)
        for (uint32_t v : t) renumber[v] = 0;
    const bool normals = mesh.normals.size() == mesh.vertices.size();
    uint32_t kept = 0;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (renumber[v] == UINT32_MAX) continue;
        renumber[v] = kept;
        mesh.vertices[kept] = mesh.vertices[v];
        if (normals) mesh.normals[kept] = mesh.normals[v];
        ++kept;
    }
    mesh.vertices.resize(kept);
    if (normals) mesh.normals.resize(kept);
    for (auto& t : mesh.triangles)
        for (uint32_t& v : t) v = renumber[v];
    return renumber;
}

}  // namespace fortu
