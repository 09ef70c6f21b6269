// libfive_mesh: times libfive's own 3D renderers on a Prospero/Fidget .vm model over [-1,1]^3,
// for bench/peers.sh (fortu's meshing and shaded-view rows beside libfive's). Ours, written
// against libfive's public API (libfive itself is built outside this repository).
//   mesh (default)  Mesh::render, dual contouring on libfive's octree, N cells per axis:
//                   min_feature is set so that the octree's finest level is exactly N cells
//                   (N a power of two), the lattice `fortu run MODEL -o m.stl --size N+1` meshes.
//   --heightmap     Heightmap::render on N x N x N voxels seen from +z (a depth map and its
//                   normals, libfive's shaded-view renderer), as `fortu -o v.png --view front
//                   --size N` draws.
// Timed (steady clock): the render call only; parsing the model, Tree::optimized() and building
// the evaluators are setup_ms, writing the mesh is not timed. One render per process.
// Usage: libfive_mesh MODEL.vm N [--heightmap] [--threads T] [--out mesh.stl]
// Prints: RESULT peer=libfive-mesh|libfive-heightmap model=... n=N threads=T eval_ms=... ...
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "libfive/eval/evaluator.hpp"
#include "libfive/render/brep/mesh.hpp"
#include "libfive/render/brep/region.hpp"
#include "libfive/render/brep/settings.hpp"
#include "libfive/render/discrete/heightmap.hpp"
#include "libfive/render/discrete/voxels.hpp"
#include "libfive/tree/tree.hpp"

using namespace libfive;
using Clock = std::chrono::steady_clock;

static double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

static bool g_uses_z = false;
static Tree load_vm(const std::string& path, size_t* nops) {
    std::ifstream in(path);
    if (!in) { std::cerr << "cannot open " << path << "\n"; exit(1); }
    std::unordered_map<std::string, size_t> names;
    std::vector<Tree> slots;
    std::string line;
    while (std::getline(in, line)) {
        size_t p = line.find_first_not_of(" \t\r");
        if (p == std::string::npos || line[p] == '#') continue;
        std::istringstream ss(line);
        std::string name, op, a, b;
        ss >> name >> op;
        auto arg = [&](const std::string& s) -> const Tree& {
            auto it = names.find(s);
            if (it == names.end()) {
                std::cerr << "unknown operand " << s << "\n"; exit(1);
            }
            return slots[it->second];
        };
        Tree t = Tree::invalid();
        if (op == "const") { ss >> a; t = Tree(std::stod(a)); }
        else if (op == "var-x") t = Tree::X();
        else if (op == "var-y") t = Tree::Y();
        else if (op == "var-z") { t = Tree::Z(); g_uses_z = true; }
        else {
            ss >> a;
            if (op == "neg") t = -arg(a);
            else if (op == "square") t = square(arg(a));
            else if (op == "sqrt") t = sqrt(arg(a));
            else if (op == "abs") t = abs(arg(a));
            else if (op == "exp") t = exp(arg(a));
            else if (op == "ln") t = log(arg(a));
            else if (op == "sin") t = sin(arg(a));
            else if (op == "cos") t = cos(arg(a));
            else {
                ss >> b;
                const Tree& ta = arg(a);
                const Tree& tb = arg(b);
                if (op == "add") t = ta + tb;
                else if (op == "sub") t = ta - tb;
                else if (op == "mul") t = ta * tb;
                else if (op == "div") t = ta / tb;
                else if (op == "max") t = max(ta, tb);
                else if (op == "min") t = min(ta, tb);
                else { std::cerr << "unknown opcode " << op << "\n"; exit(1); }
            }
        }
        names[name] = slots.size();
        slots.push_back(t);
    }
    *nops = slots.size();
    return slots.back();
}

static int usage() {
    std::cerr << "usage: libfive_mesh MODEL.vm N [--heightmap] [--threads T] [--out mesh.stl]\n";
    return 2;
}

int main(int argc, char** argv) {
    if (argc < 3) return usage();
    const std::string model = argv[1];
    const int n = std::atoi(argv[2]);
    if (n < 2 || n > 4096) { std::cerr << "libfive_mesh: N must be in [2, 4096]\n"; return 2; }
    int threads = 1;
    bool heightmap = false;
    std::string out;
    for (int i = 3; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--heightmap") heightmap = true;
        else if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (a == "--out" && i + 1 < argc) out = argv[++i];
        else return usage();
    }
    if (threads < 1) { std::cerr << "libfive_mesh: --threads must be positive\n"; return 2; }

    auto t0 = Clock::now();
    size_t nops = 0;
    const Tree optimized = load_vm(model, &nops).optimized();
    // Eigen-aligned, contiguous: Mesh::render takes a pointer to `workers` evaluators.
    std::vector<Evaluator, Eigen::aligned_allocator<Evaluator>> es;
    es.reserve(threads);
    for (int i = 0; i < threads; ++i) es.emplace_back(Evaluator(optimized));
    const double setup_ms = ms_since(t0);
    const std::string name = model.substr(model.find_last_of('/') + 1);

    if (heightmap) {
        // N voxels per axis over [-1,1]^3 (res = voxels per unit); depth runs along z.
        Voxels region({-1, -1, -1}, {1, 1, 1}, n / 2.0f);
        std::vector<Evaluator*> ptrs;
        for (auto& e : es) ptrs.push_back(&e);
        std::atomic_bool abort(false);
        t0 = Clock::now();
        auto map = Heightmap::render(ptrs, region, abort);
        const double ms = ms_since(t0);
        size_t filled = 0;
        for (int j = 0; j < map->depth.rows(); ++j)
            for (int i = 0; i < map->depth.cols(); ++i) filled += std::isfinite(map->depth(j, i));
        printf("RESULT peer=libfive-heightmap model=%s n=%d threads=%d eval_ms=%.2f setup_ms=%.1f "
               "pixels=%zux%zu depth_samples=%zu filled=%zu ops=%zu\n",
               name.c_str(), n, threads, ms, setup_ms, region.pts[0].size(), region.pts[1].size(),
               region.pts[2].size(), filled, nops);
        return 0;
    }

    BRepSettings settings;
    // withResolution() takes ceil(log2(2 / min_feature)) levels: a feature size a hair above
    // 2/N gives exactly log2(N) levels, whatever logf rounds to.
    settings.min_feature = 2.0 / n * 1.001;
    settings.workers = threads;
    const Region<3> region({-1, -1, -1}, {1, 1, 1});
    const int cells = 1 << region.withResolution(settings.min_feature).level;
    if (cells != n)  // the octree halves the region: only a power of two is exact
        std::cerr << "libfive_mesh: note: libfive's octree has " << cells << " cells per axis, not " << n << "\n";
    t0 = Clock::now();
    auto mesh = Mesh::render(es.data(), region, settings);
    const double ms = ms_since(t0);
    if (!mesh) { std::cerr << "libfive_mesh: Mesh::render failed\n"; return 1; }
    if (!out.empty() && !mesh->saveSTL(out)) { std::cerr << "libfive_mesh: cannot write " << out << "\n"; return 1; }
    printf("RESULT peer=libfive-mesh model=%s n=%d cells=%d threads=%d eval_ms=%.2f setup_ms=%.1f "
           "triangles=%zu vertices=%zu ops=%zu\n",
           name.c_str(), n, cells, threads, ms, setup_ms, mesh->branes.size(),
           mesh->verts.size() - 1, nops);
    return 0;
}
