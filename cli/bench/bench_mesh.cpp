// cli/bench/bench_mesh.cpp — the mesh benchmark's loop and table.
#include "cli/bench/bench_mesh.hpp"

#include "interp/mesher.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>

namespace fortu {

int run_mesh_benchmarks(const std::vector<std::string>& models, const std::vector<int>& sizes,
                        const MeasureOptions& options) {
    int status = 0;
    std::cout << fmt::format("{:<28} {:>14} {:>11} {:>11} {:>10} {:>10} {:>11} {:>11}\n", "model", "nodes", "triangles",
                             "vertices", "median", "min", "peak RSS", "growth");
    for (const std::string& path : models) {
        std::optional<Model> model = load_bench_model(path);
        if (!model) { status = 1; continue; }
        if (model->dims() != 3) {
            std::cerr << fmt::format("fortu: error: {}: a mesh needs a 3D model\n", path);
            status = 1;
            continue;
        }
        for (int size : sizes) {
            const Grid grid = bench_grid(*model, size);
            EvalOptions eval;
            eval.threads = options.threads;
            std::vector<double> seconds;
            std::size_t triangles = 0, vertices = 0, peak = 0, growth = 0;
            double total = 0;
            for (int run = 0; run < std::max(1, options.repeat) && (run == 0 || total < options.repeat_cap); ++run) {
                const PeakMemoryProbe memory;
                Stopwatch clock;
                const Mesh mesh = extract_mesh(model->graph, model->root, grid, eval);
                seconds.push_back(clock.seconds());
                total += seconds.back();
                triangles = mesh.triangles.size();
                vertices = mesh.vertices.size();
                peak = std::max(peak, memory.peak());
                growth = std::max(growth, memory.growth());
            }
            std::vector<double> sorted = seconds;
            std::sort(sorted.begin(), sorted.end());
            const double median = (sorted[(sorted.size() - 1) / 2] + sorted[sorted.size() / 2]) / 2;
            std::cout << fmt::format("{:<28} {:>14} {:>11} {:>11} {:>10} {:>10} {:>11} {:>11}\n",
                                     path.substr(path.find_last_of('/') + 1), grid_text(grid),
                                     format_count(triangles), format_count(vertices),
                                     format_duration(median), format_duration(sorted.front()),
                                     format_bytes(peak), format_bytes(growth));
        }
    }
    return status;
}

}  // namespace fortu
