// interp/point_list.cpp — tiles of caller-given points through the one lane kernel.
#include "interp/point_list.hpp"

#include "interp/lane_kernel.hpp"
#include "interp/parallel.hpp"
#include "interp/voxel_engine.hpp"

#include <algorithm>
#include <vector>

namespace fortu {
namespace {

/// One worker's slots: kTileSize lanes each, the constants filled once.
struct Lanes {
    std::vector<double> storage;
    std::vector<double*> slots;

    Lanes(const Tape& tape, int lanes) : storage(static_cast<std::size_t>(tape.slot_count) * lanes, 0.0) {
        slots.resize(tape.slot_count);
        for (uint32_t s = 0; s < tape.slot_count; ++s) slots[s] = storage.data() + static_cast<std::size_t>(s) * lanes;
        for (auto [slot, value] : tape.constants) std::fill_n(slots[slot], lanes, value);
    }
};

}  // namespace

PointListEvaluator::PointListEvaluator(const ir::Graph& graph, ir::NodeId root) : tape_(compile_tape(graph, root)) {}

double PointListEvaluator::value(std::array<double, 3> point) const {
    Lanes lanes(tape_, 1);
    for (auto [slot, axis] : tape_.arguments) lanes.slots[slot][0] = point[axis];
    run_lanes<double, 1>(tape_.code.data(), tape_.code.size(), lanes.slots.data(), 1);
    return lanes.slots[tape_.root_slot][0];
}

void PointListEvaluator::values(std::size_t points, const Coordinates& coordinates, double* out,
                                const EvalOptions& options) const {
    const std::size_t tiles = (points + kTileSize - 1) / kTileSize;
    std::vector<Lanes> workers;
    for (int w = 0; w < worker_count(tiles, options); ++w) workers.emplace_back(tape_, kTileSize);
    parallel_for(tiles, options, [&](std::size_t tile, int worker) {
        Lanes& lanes = workers[static_cast<std::size_t>(worker)];
        const std::size_t first = tile * kTileSize;
        const int count = static_cast<int>(std::min<std::size_t>(kTileSize, points - first));
        // Axes the model does not use still need somewhere to go.
        double* axis[3] = {nullptr, nullptr, nullptr};
        std::array<double, kTileSize> unused[3];
        for (int a = 0; a < 3; ++a) axis[a] = unused[a].data();
        for (auto [slot, a] : tape_.arguments) axis[a] = lanes.slots[slot];
        coordinates(first, count, axis[0], axis[1], axis[2]);
        if (count == kTileSize) run_lanes<double, kTileSize>(tape_.code.data(), tape_.code.size(), lanes.slots.data(), count);
        else run_lanes<double, 0>(tape_.code.data(), tape_.code.size(), lanes.slots.data(), count);
        std::copy_n(lanes.slots[tape_.root_slot], count, out + first);
        return static_cast<std::size_t>(count);
    });
}

}  // namespace fortu
