// tests/tools/mesh_check.cpp — fortu_mesh_check: the independent mesh check of the tests
// (unit/mesh_checker.hpp) on one mesh fortu wrote, for measuring what the tests bound: its
// topology, and its distances to the model's true surface both ways in cells.
// Why a tool: the acceptance bound (half a cell on every 3D RANOK script) is measured at many
// sizes and with more samples than a test can afford; bench/mesh_accuracy.sh runs it.
//
// Usage: fortu_mesh_check MODEL MESH STATS [--samples N] [--far]
//   MODEL  the .fortu or .vm file meshed; MESH its binary .ply or .stl; STATS what
//   `fortu run MODEL ... -o MESH --stats` printed (its lattice line gives the nodes and box).
//   --samples N  surface samples from (N + 1)³ lattice points (default 24; the tests use 12);
//   --far        also list each sample more than half a cell from the mesh.
#include "../unit/mesh_checker.hpp"

#include "grammar/diagnostic.hpp"
#include "interp/lower.hpp"
#include "interp/vm_import.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <iostream>

using namespace fortu;

namespace {

int usage(const std::string& why) {
    std::cerr << "fortu_mesh_check: " << why << "\nusage: fortu_mesh_check MODEL MESH STATS [--samples N] [--far]\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> files;
    int samples = 24;
    bool list_far = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--far") {
            list_far = true;
        } else if (arg == "--samples") {
            if (++i == argc) return usage("--samples needs a number");
            char* end = nullptr;
            const long n = std::strtol(argv[i], &end, 10);
            if (*end != '\0' || n < 1 || n > 1000) return usage("--samples takes a whole number from 1 to 1000");
            samples = int(n);
        } else {
            files.push_back(arg);
        }
    }
    if (files.size() != 3) return usage("three files are needed");
    try {
        std::string error;
        auto source = SourceFile::load(files[0], error);
        if (!source) return usage(error);
        CompileOptions options;
        options.include_dirs = {std::string(FORTU_SOURCE_DIR) + "/stdlib"};
        DiagnosticSink sink;
        std::optional<Model> model = is_vm_path(files[0]) ? import_vm(source, sink) : compile(source, options, sink);
        if (!model) {
            std::cerr << sink.render_all();
            return 1;
        }
        const std::string stats = test::file_bytes(files[2]);
        const std::size_t at = stats.find(" nodes, x [");
        test::P3 lo{}, hi{};
        int nodes[3] = {0, 0, 0};
        if (at == std::string::npos ||
            std::sscanf(stats.c_str() + at, " nodes, x [%lf, %lf], y [%lf, %lf], z [%lf, %lf]", &lo[0], &hi[0], &lo[1],
                        &hi[1], &lo[2], &hi[2]) != 6 ||
            std::sscanf(stats.c_str() + stats.rfind(' ', at - 1) + 1, "%dx%dx%d", &nodes[0], &nodes[1], &nodes[2]) != 3)
            return usage(files[2] + " has no lattice line (\"mesh: ... NxNxN nodes, x [..], y [..], z [..]\"): run fortu with --stats");
        double h = 0;
        for (int k = 0; k < 3; ++k) h = std::max(h, (hi[k] - lo[k]) / std::max(nodes[k] - 1, 1));
        const bool stl = files[1].size() > 4 && files[1].compare(files[1].size() - 4, 4, ".stl") == 0;
        const test::CheckedMesh mesh = stl ? test::read_binary_stl(files[1]) : test::read_binary_ply(files[1]);
        const PointEvaluator field(model->graph, model->root);
        std::vector<std::pair<test::P3, double>> far;
        const test::MeshCheck r = test::check_mesh(mesh, field, lo, hi, h, samples, list_far ? &far : nullptr);
        // A sample with no triangle in the cells round it is more than a cell off (the checker
        // looks no farther).
        auto cells = [&](double d) { return d > 1e100 ? std::string(">1") : fmt::format("{:.3f}", d / h); };
        std::printf("triangles %zu open %zu overused %zu same-direction %zu degenerate %zu intersecting %zu volume %.6g "
                    "normals-wrong %zu/%zu mesh-to-surface %s surface-to-mesh %s samples %zu worst %s\n",
                    r.triangles, r.open_edges, r.overused_edges, r.same_direction_edges, r.degenerate, r.intersecting_pairs,
                    r.signed_volume, r.normals_wrong, r.normals_checked, cells(r.mesh_to_surface).c_str(),
                    cells(r.surface_to_mesh).c_str(), r.samples, test::worst_points(r).c_str());
        for (const auto& [p, d] : far) std::printf("far %.6f %.6f %.6f %.4f\n", p[0], p[1], p[2], d / h);
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "fortu_mesh_check: " << e.what() << "\n";
        return 1;
    }
}
