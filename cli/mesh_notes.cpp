// cli/mesh_notes.cpp — the sentences of mesh_notes.hpp.
#include "cli/mesh_notes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace fortu {

std::vector<std::string> mesh_notes(const MeshStats& stats, const Grid& grid) {
    std::vector<std::string> notes;
    // Sharp edges: the bound the mesh otherwise keeps is half a cell.
    const CoverStats& cover = stats.cover;
    if (cover.crossings_off_mesh > 0 && !(cover.farthest_crossing_off <= 0.5)) {
        const std::string farthest = std::isfinite(cover.farthest_crossing_off)
                                         ? fmt::format("up to {:.3g} cells", cover.farthest_crossing_off)
                                         : "more than a cell";
        notes.push_back(fmt::format("sharp edges are off the mesh by {} at {} points where they cross cell faces ({} such "
                                    "points are on it): wedges thinner than a cell whose cells could not be redone",
                                    farthest, cover.crossings_off_mesh, stats.features.edge_vertices));
    }
    if (stats.refinement_left > 0) {
        // A centre on a symmetric domain's middle plane is zero to round-off: shown as 0.
        const double scale = std::max({grid.x.max - grid.x.min, grid.y.max - grid.y.min, grid.z.max - grid.z.min});
        auto shown = [&](double v) { return std::fabs(v) < 1e-12 * scale ? 0.0 : v; };
        notes.push_back(fmt::format("parts of the solid thinner than a cell (or holes in it) go on beyond the {} cells "
                                    "refined for them, and are missing from the mesh in {} more cells, the first at "
                                    "({:.6g}, {:.6g}, {:.6g}): at a --size whose cells are smaller than the part is thick, "
                                    "the lattice itself meshes it",
                                    stats.refined_cells, stats.refinement_left, shown(stats.first_left[0]),
                                    shown(stats.first_left[1]), shown(stats.first_left[2])));
    }
    return notes;
}

}  // namespace fortu
