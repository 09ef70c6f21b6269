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

}  // namespace fortu
