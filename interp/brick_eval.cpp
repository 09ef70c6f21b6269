// interp/brick_eval.cpp — bricks of a grid and their pruned, exact evaluation (brick_eval.hpp):
// an octree inside each brick, each box's intervals shorten the tape for its sub-boxes
// (keep_values: the root's value stays bit for bit) or, for sparse writers, skip it.
#include "interp/brick_eval.hpp"

#include "interp/box_halving.hpp"
#include "interp/box_simplify.hpp"
#include "interp/interval.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/tape.hpp"
#include "interp/written_r_operations.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fortu {
namespace {

/// Boxes of at most 8 nodes per axis are leaves when a band lets boxes be skipped (a thin
/// band is found at that resolution), 32 when every value is wanted (then a box only
/// shortens its tape, and smaller boxes cost more in intervals and simplification than
/// they save: tanglecube.vm 512³ took 3x the in-memory CPU time with 8³ leaves).
/// Their points run in batches of 256 lanes (the sign renderer's batch; more lanes would
/// multiply the scratch by a large model's thousands of SSA slots).
constexpr int kSparseLeafEdge = 8;
constexpr int kDenseLeafEdge = 32;
constexpr int kLanes = 256;

}  // namespace

struct BrickEvaluator::Impl {
    const Grid grid;
    Tape tape;                                  ///< SSA, the whole model
    std::vector<std::unique_ptr<Tape>> tapes;   ///< one shortened tape per depth
    std::vector<Interval> ranges;
    BoxScratch scratch;
    std::vector<double> lanes;
    std::vector<double*> slots;
    std::array<std::vector<double>, 3> coords;   ///< a leaf's coordinates per axis
    int lane_at[3][kLanes];                      ///< each lane's index into coords, per axis
    // The brick being evaluated.
    BrickBox brick;
    double* out = nullptr;
    std::optional<double> skip_beyond;
    BrickStats stats;

    Impl(const ir::Graph& graph, ir::NodeId root, const Grid& g)
        : grid(g), tape(pruning_tape(graph, root)) {}

    double at(int axis, int i) const { return axis == 0 ? grid.x_at(i) : axis == 1 ? grid.y_at(i) : grid.z_at(i); }

    std::size_t local(int c, int r, int s) const { return brick.local(c, r, s); }

    void fill(const BrickBox& box, double value) {
        for (int s = box.lo[2]; s <= box.hi[2]; ++s)
            for (int r = box.lo[1]; r <= box.hi[1]; ++r) std::fill_n(out + local(box.lo[0], r, s), box.extent()[0], value);
        stats.skipped_points += box.points();
    }

    void walk(const BrickBox& box, const Tape& parent, std::size_t depth) {
        if (tapes.size() <= depth) tapes.push_back(std::make_unique<Tape>());
        Tape& shortened = *tapes[depth];
        std::array<Interval, 3> axes;
        for (int a = 0; a < 3; ++a) {
            const double p = at(a, box.lo[a]), q = at(a, box.hi[a]);
            axes[a] = {std::min(p, q), std::max(p, q), false};
        }
        evaluate_intervals(parent, axes, ranges);
        const Interval r = ranges[parent.root_slot];
        if (skip_beyond && !r.maybe_nan && (r.lo > *skip_beyond || r.hi < -*skip_beyond)) {
            fill(box, r.lo > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
            return;
        }
        simplify_for_sign(parent, ranges, scratch, shortened, /*keep_values=*/true);
        const std::array<int, 3> e = box.extent();
        const int leaf = skip_beyond ? kSparseLeafEdge : kDenseLeafEdge;
        if (e[0] <= leaf && e[1] <= leaf && e[2] <= leaf) {
            evaluate_points(box, shortened);
            return;
        }
        // Halve every axis longer than a leaf.
        for (const BrickBox& part : halve_axes(box, [&](int a) { return e[a] > leaf; }))
            walk(part, shortened, depth + 1);
    }

    void evaluate_points(const BrickBox& box, const Tape& t) {
        if (lanes.size() < std::size_t(t.slot_count) * kLanes) lanes.resize(std::size_t(t.slot_count) * kLanes);
        slots.resize(t.slot_count);
        for (uint32_t s = 0; s < t.slot_count; ++s) slots[s] = lanes.data() + std::size_t(s) * kLanes;
        std::fill_n(slots[t.zero_slot], kLanes, 0.0);
        for (auto [slot, value] : t.constants) std::fill_n(slots[slot], kLanes, value);
        const std::array<int, 3> e = box.extent();
        const int count = int(box.points());
        // Each axis's coordinates once per box; the lanes walk the box with counters.
        for (int a = 0; a < 3; ++a) {
            coords[a].resize(e[a]);
            for (int i = 0; i < e[a]; ++i) coords[a][i] = at(a, box.lo[a] + i);
        }
        std::size_t targets[kLanes];
        int c = 0, r = 0, z = 0;
        for (int first = 0; first < count; first += kLanes) {
            const int n = std::min(kLanes, count - first);
            for (int l = 0; l < n; ++l) {
                lane_at[0][l] = c;
                lane_at[1][l] = r;
                lane_at[2][l] = z;
                targets[l] = local(box.lo[0] + c, box.lo[1] + r, box.lo[2] + z);
                if (++c == e[0]) {
                    c = 0;
                    if (++r == e[1]) r = 0, ++z;
                }
            }
            for (auto [slot, axis] : t.arguments) {
                double* lanes_out = slots[slot];
                const double* axis_coords = coords[axis].data();
                const int* index = lane_at[axis];
                for (int l = 0; l < n; ++l) lanes_out[l] = axis_coords[index[l]];
            }
            if (n == kLanes) run_lanes<double, kLanes>(t.code.data(), t.code.size(), slots.data(), n);
            else run_lanes<double, 0>(t.code.data(), t.code.size(), slots.data(), n);
            const double* result = slots[t.root_slot];
            for (int l = 0; l < n; ++l) out[targets[l]] = result[l];
        }
        stats.evaluated_points += std::size_t(count);
        stats.operations += std::size_t(count) * t.code.size();
    }
};

BrickEvaluator::BrickEvaluator(const ir::Graph& graph, ir::NodeId root, const Grid& grid)
    : impl_(std::make_unique<Impl>(graph, root, grid)) {}

BrickEvaluator::~BrickEvaluator() = default;

BrickStats BrickEvaluator::evaluate(const BrickBox& box, std::vector<double>& values, std::optional<double> skip_beyond) {
    values.resize(box.points());
    Impl& m = *impl_;
    m.brick = box;
    m.out = values.data();
    m.skip_beyond = skip_beyond;
    m.stats = {};
    m.walk(box, m.tape, 0);
    return m.stats;
}

std::size_t brick_evaluator_bytes(const ir::Graph& graph, ir::NodeId root) {
    const Tape tape = pruning_tape(graph, root);
    // Lanes, ranges, and shortened tapes (at most the whole tape per depth, ~6 depths).
    return std::size_t(tape.slot_count) * (kLanes * sizeof(double) + sizeof(Interval) + 64) +
           8 * tape.code.size() * sizeof(Instruction);
}

}  // namespace fortu
