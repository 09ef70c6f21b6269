// interp/voxel_engine.cpp — the tape evaluated tile by tile, each node once per point.
#include "interp/voxel_engine.hpp"

#include "interp/ir/kernels.hpp"
#include "interp/parallel.hpp"

#include <algorithm>
#include <vector>

namespace fortu {
namespace {

using namespace ir;  // kernel names are used unqualified inside ops.def expressions

/// Runs the tape over `lanes` points whose argument slots are already filled. The switch
/// is outside the lane loop, so each case is a tight loop the compiler vectorises.
template <class T>
void run_tape(const Tape& tape, T* slots, int stride, int lanes) {
    for (const Instruction& ins : tape.code) {
        T* out = slots + static_cast<std::size_t>(ins.out) * stride;
        const T* A = slots + static_cast<std::size_t>(ins.in[0]) * stride;
        const T* B = slots + static_cast<std::size_t>(ins.in[1]) * stride;
        const T* C = slots + static_cast<std::size_t>(ins.in[2]) * stride;
        [[maybe_unused]] const double imm = ins.imm;
        switch (ins.op) {
#define FORTU_OP(name, arity, spelling, flags, formula_ops, expr)          \
    case Op::name:                                                         \
        for (int l = 0; l < lanes; ++l) {                                  \
            [[maybe_unused]] const T a = A[l];                             \
            [[maybe_unused]] const T b = B[l];                             \
            [[maybe_unused]] const T c = C[l];                             \
            [[maybe_unused]] auto get_a = value_of(a);                     \
            [[maybe_unused]] auto get_b = value_of(b);                     \
            out[l] = (expr);                                               \
        }                                                                  \
        break;
#include "interp/ir/ops.def"
#undef FORTU_OP
        }
    }
}

/// The grid in tiles of kTileSize points, each tile's slots in the number type T.
template <class T>
void evaluate_tiles(const Tape& tape, Field& field, const EvalOptions& options) {
    const Grid& grid = field.grid;
    const std::size_t points = grid.points();
    const std::size_t tiles = (points + kTileSize - 1) / kTileSize;
    const std::size_t plane = static_cast<std::size_t>(grid.cols()) * grid.rows();

    // One slot buffer per worker, allocated before the loop and reused for all its tiles
    // (nothing is allocated per tile); constants are filled once.
    std::vector<std::vector<T>> workspaces(worker_count(tiles, options));
    for (std::vector<T>& slots : workspaces) {
        slots.assign(static_cast<std::size_t>(tape.slot_count) * kTileSize, T(0));
        for (auto [slot, value] : tape.constants)
            std::fill_n(slots.begin() + static_cast<std::ptrdiff_t>(slot) * kTileSize, kTileSize, T(value));
    }

    parallel_for(tiles, options, [&](std::size_t tile, int worker) {
        T* slots = workspaces[worker].data();
        const std::size_t start = tile * kTileSize;
        const int lanes = static_cast<int>(std::min<std::size_t>(kTileSize, points - start));
        for (auto [slot, axis] : tape.arguments) {
            T* lane_values = slots + static_cast<std::size_t>(slot) * kTileSize;
            for (int l = 0; l < lanes; ++l) {
                const std::size_t p = start + l;
                lane_values[l] = T(axis == 0 ? grid.x_at(static_cast<int>(p % grid.cols()))
                                 : axis == 1 ? grid.y_at(static_cast<int>((p / grid.cols()) % grid.rows()))
                                             : grid.z_at(static_cast<int>(p / plane)));
            }
        }
        run_tape(tape, slots, kTileSize, lanes);
        const T* result = slots + static_cast<std::size_t>(tape.root_slot) * kTileSize;
        double* out = field.values.data() + start;
        for (int l = 0; l < lanes; ++l) out[l] = double(result[l]);
        return static_cast<std::size_t>(lanes);
    });
}

}  // namespace

void voxel_evaluate_grid(const ir::Graph& graph, ir::NodeId root, Field& field, const EvalOptions& options) {
    const Tape tape = compile_tape(graph, root);
    if (options.precision == Precision::Float32) evaluate_tiles<float>(tape, field, options);
    else evaluate_tiles<double>(tape, field, options);
}

PointEvaluator::PointEvaluator(const ir::Graph& graph, ir::NodeId root) : tape_(compile_tape(graph, root)) {}

PointValue PointEvaluator::operator()(std::array<double, 3> point) const {
    std::vector<Dual> slots(tape_.slot_count, Dual(0.0));
    for (auto [slot, value] : tape_.constants) slots[slot] = Dual(value);
    for (auto [slot, axis] : tape_.arguments) slots[slot] = Dual::variable(point[axis], axis);
    run_tape(tape_, slots.data(), 1, 1);
    const Dual& r = slots[tape_.root_slot];
    return PointValue{r.v, {r.d[0], r.d[1], r.d[2]}};
}

}  // namespace fortu
