// cli/mesh_output.cpp — run's mesh path: mesh, write, report.
#include "cli/mesh_output.hpp"

#include "cli/mesh_notes.hpp"
#include "cli/model_setup.hpp"
#include "cli/option_table.hpp"
#include "cli/standard_streams.hpp"
#include "interp/ir_print.hpp"
#include "interp/mesh_refine.hpp"
#include "interp/mesher.hpp"
#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/progress.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <string>

namespace fortu {

namespace {

/// How far the farthest crossing left off the mesh is, for --stats: none is sought beyond a
/// cell of the finished mesh.
std::string farthest_off(const CoverStats& cover) {
    if (cover.crossings_off_mesh == 0) return "";
    if (!std::isfinite(cover.farthest_crossing_off)) return " (the farthest more than a cell)";
    return fmt::format(" (the farthest {:.3g} cells)", cover.farthest_crossing_off);
}

}  // namespace

bool is_mesh_output(const std::string& path) {
    const OutputFormat* format = path.empty() ? nullptr : output_format_for(path);
    return format && format->kind == OutputKind::Mesh;
}

int run_mesh_output(const Model& model, const Grid& grid, const CliOptions& o, double compile_seconds) {
    if (const std::optional<MeshRefusal> refusal = mesh_refusal(model, grid))
        throw UsageError(refusal->size_at_fault ? "--size: " + refusal->message
                                                : fmt::format("-o {}: {}", o.output, refusal->message));
    EvalOptions eval;
    eval.threads = o.threads;
    Stopwatch clock;
    MeshStats stats;
    const Mesh mesh = extract_mesh(model.graph, model.root, grid, eval, &stats);
    const double mesh_seconds = clock.seconds();
    const std::size_t mesh_peak = peak_rss_bytes();
    Stopwatch write_clock;
    OutputOptions out;
    out.ascii = o.ascii;
    try {
        write_mesh(mesh, resolve_output(o.output), out);
    } catch (const OutputError& e) {
        std::cerr << fmt::format("fortu: error: {}\n", e.what());
        return 1;
    }
    const double write_seconds = write_clock.seconds();
    if (mesh.triangles.empty())
        std::cerr << fmt::format("fortu: warning: the surface does not cross the domain x [{}, {}], y [{}, {}], "
                                 "z [{}, {}]: the mesh is empty\n",
                                 grid.x.min, grid.x.max, grid.y.min, grid.y.max, grid.z.min, grid.z.max);
    if (!o.quiet)
        std::cerr << fmt::format("wrote {} ({} triangles)\n", shown_output_path(o.output), mesh.triangles.size());
    for (const std::string& note : mesh_notes(stats, grid)) std::cerr << "fortu: note: " << note << '\n';
    std::ostream& report = report_stream(o);
    if (!o.stats) {
        report << fmt::format("{}: {} triangles, {} vertices on {}x{}x{} nodes in {}; wrote {}\n",
                              shown_script_name(o.positional[0]), mesh.triangles.size(), mesh.vertices.size(),
                              grid.cols(), grid.rows(), grid.slices(), format_duration(mesh_seconds),
                              shown_output_path(o.output));
        return 0;
    }
    report << fmt::format(
        "model: {}\nmesh: {} triangles, {} vertices, {}x{}x{} nodes, x [{}, {}], y [{}, {}], z [{}, {}]\n"
        "octree: {} boxes tested, {} leaves of 8^3 cells, {} nodes evaluated ({:.2f}% of {}), "
        "{} edge solves for {} vertices\n"
        "thin parts: {} cells with a part thinner than a cell, {} cells off the mesh refined with those the parts go on "
        "into: {} cells {} times finer, {} joining them, {} left out\n"
        "sharp features: {} cells tested, {} vertices on edges, {} at corners, {} mesh edges along them, "
        "{} edge crossings off the mesh{}\n"
        "surface probes: {} points projected, {} more than {} cells from the mesh: {} put in, {} covered by those, "
        "{} refused{}\n"
        "time: compile {:.3f} s, mesh {:.3f} s, write {:.3f} s\n"
        "peak memory: {} meshing, {} in all\n",
        shown_script_name(o.positional[0]), mesh.triangles.size(), mesh.vertices.size(), grid.cols(), grid.rows(),
        grid.slices(),
        grid.x.min, grid.x.max, grid.y.min, grid.y.max, grid.z.min, grid.z.max, stats.boxes, stats.leaves,
        stats.node_evaluations, 100.0 * double(stats.node_evaluations) / double(grid.points()),
        format_operations(double(grid.points())), stats.edge_evaluations, stats.crossing_edges, stats.thin_cells,
        stats.refine_seeds, stats.refined_cells, kRefine, stats.transition_cells, stats.refinement_left,
        stats.features.cells_tested,
        stats.features.edge_vertices, stats.features.corner_vertices, stats.features.chain_edges,
        stats.cover.crossings_off_mesh, farthest_off(stats.cover), stats.cover.probes, stats.cover.far,
        kCoverDistance, stats.cover.inserted, stats.cover.covered, stats.cover.refused,
        stats.cover.refused ? fmt::format(" (the farthest {:.3f} cells)", stats.cover.farthest_left) : "", compile_seconds,
        mesh_seconds, write_seconds, format_bytes(mesh_peak), format_bytes(peak_rss_bytes()));
    return 0;
}

}  // namespace fortu
