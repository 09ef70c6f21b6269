// cli/bench/bench_mesh.hpp — `fortu bench MODEL... --mesh`: times the mesher (interp/mesher.hpp)
// per model and size, with the mesh's size and the peak memory, as `fortu run -o F.stl`
// meshes (writing excluded).
#pragma once

#include "cli/bench/bench_measure.hpp"

#include <string>
#include <vector>

namespace fortu {

/// Meshes each model at each size (nodes per axis) `options.repeat` times and prints a table;
/// returns the exit status (1 when a model does not load or is not 3D).
int run_mesh_benchmarks(const std::vector<std::string>& models, const std::vector<int>& sizes,
                        const MeasureOptions& options);

}  // namespace fortu
