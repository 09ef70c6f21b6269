// interp/voxel_engine.cpp — the tape evaluated tile by tile, each node once per point.
#include "interp/voxel_engine.hpp"

#include "interp/ir/kernels.hpp"
#include "interp/parallel.hpp"

#include <algorithm>
#include <vector>

namespace fortu {
namespace {

using namespace ir;  // kernel names are used unqualified inside ops.def expressions

/// Runs the tape over kLanes points whose argument slots are already filled (a fixed
/// count, so the loops compile without remainder handling). The switch
/// is outside the lane loop, so each case is a tight loop the compiler vectorises; an
/// operand that is a constant is read from a register, one loop per combination that
/// occurs after constant folding (none, the first or the second operand constant).
template <class T, int kLanes>
void run_tape(const Tape& tape, T* slots) {
    for (const Instruction& ins : tape.code) {
        T* __restrict out = slots + static_cast<std::size_t>(ins.out) * kLanes;
        const T* __restrict A = slots + static_cast<std::size_t>(ins.in[0]) * kLanes;
        const T* __restrict B = slots + static_cast<std::size_t>(ins.in[1]) * kLanes;
        const T* __restrict C = slots + static_cast<std::size_t>(ins.in[2]) * kLanes;
        [[maybe_unused]] const double imm = ins.imm;
        [[maybe_unused]] const T ka = T(ins.constant[0]);
        [[maybe_unused]] const T kb = T(ins.constant[1]);
        [[maybe_unused]] const T kc = T(ins.constant[2]);
        const unsigned mask = ins.constant_operands;
        switch (ins.op) {
#define FORTU_LANES(expr, a_value, b_value, c_value)                       \
    for (int l = 0; l < kLanes; ++l) {                                     \
        [[maybe_unused]] const T a = (a_value);                            \
        [[maybe_unused]] const T b = (b_value);                            \
        [[maybe_unused]] const T c = (c_value);                            \
        [[maybe_unused]] auto get_a = value_of(a);                         \
        [[maybe_unused]] auto get_b = value_of(b);                         \
        out[l] = (expr);                                                   \
    }
#define FORTU_OP(name, arity, spelling, flags, formula_ops, expr)          \
    case Op::name:                                                         \
        if (mask == 0) { FORTU_LANES(expr, A[l], B[l], C[l]) }             \
        else if (mask == 1) { FORTU_LANES(expr, ka, B[l], C[l]) }          \
        else if (mask == 2) { FORTU_LANES(expr, A[l], kb, C[l]) }          \
        else { FORTU_LANES(expr, (mask & 1) ? ka : A[l], (mask & 2) ? kb : B[l], (mask & 4) ? kc : C[l]) } \
        break;
#include "interp/ir/ops.def"
#undef FORTU_OP
#undef FORTU_LANES
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
            // A partial last tile repeats its last point in the unused lanes.
            for (int l = 0; l < kTileSize; ++l) {
                const std::size_t p = start + std::min(l, lanes - 1);
                lane_values[l] = T(axis == 0 ? grid.x_at(static_cast<int>(p % grid.cols()))
                                 : axis == 1 ? grid.y_at(static_cast<int>((p / grid.cols()) % grid.rows()))
                                             : grid.z_at(static_cast<int>(p / plane)));
            }
        }
        run_tape<T, kTileSize>(tape, slots);
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
    run_tape<Dual, 1>(tape_, slots.data());
    const Dual& r = slots[tape_.root_slot];
    return PointValue{r.v, {r.d[0], r.d[1], r.d[2]}};
}

}  // namespace fortu
