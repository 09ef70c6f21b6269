// tests/unit/runtime_mesh_test.cpp — the mesh type's one operation: dropping the vertices no
// triangle uses (the mesher's refinement and sharp-feature pass both end with it).
#include "runtime/mesh.hpp"

#include <doctest/doctest.h>

using namespace fortu;

TEST_CASE("unused vertices are dropped, the others keep their order and the triangles follow") {
    Mesh mesh;
    for (int v = 0; v < 6; ++v) {
        mesh.vertices.push_back({double(v), 0, 0});
        mesh.normals.push_back({0, 0, double(v)});
    }
    mesh.triangles = {{5, 1, 3}, {3, 1, 4}};  // 0 and 2 unused
    const std::vector<uint32_t> renumber = drop_unused_vertices(mesh);
    CHECK(renumber == std::vector<uint32_t>{UINT32_MAX, 0, UINT32_MAX, 1, 2, 3});
    CHECK(mesh.vertices == std::vector<std::array<double, 3>>{{1, 0, 0}, {3, 0, 0}, {4, 0, 0}, {5, 0, 0}});
    CHECK(mesh.normals == std::vector<std::array<double, 3>>{{0, 0, 1}, {0, 0, 3}, {0, 0, 4}, {0, 0, 5}});
    CHECK(mesh.triangles == std::vector<std::array<uint32_t, 3>>{{3, 0, 1}, {1, 0, 2}});
    // A mesh without normals keeps none.
    Mesh bare{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {}, {{1, 2, 3}}};
    drop_unused_vertices(bare);
    CHECK(bare.vertices.size() == 3);
    CHECK(bare.normals.empty());
    CHECK(bare.triangles == std::vector<std::array<uint32_t, 3>>{{0, 1, 2}});
}
