// interp/domain_auto.cpp — level-by-level interval subdivision of the search cube.
#include "interp/domain_auto.hpp"

#include "interp/box_simplify.hpp"
#include "interp/engine.hpp"
#include "interp/interval.hpp"
#include "interp/tape.hpp"
#include "interp/written_r_operations.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <queue>
#include <fmt/format.h>
#include <vector>

namespace fortu {
namespace {

struct Cell {
    double lo[3], hi[3];
};

constexpr std::size_t kMaxCells = 1 << 16;  ///< cells halved per bound at most
/// Cells halved per bound in the first round, which looks for a side the solid reaches. Why:
/// where the solid reaches the cube's faces, one side usually shows it within a few thousand
/// cells while another spends the whole kMaxCells on a bound inside the cube (ConceptLopatka:
/// 65,537 cells for x ≤ 9.5 in the ±16 cube, then 87 for y reaching −16), 0.06 s → 2.4 s
/// once its written R-operations made the intervals tight enough to search at all.
constexpr std::size_t kQuickCells = 1 << 12;
/// A bound is settled by a cell of 1/(16 · this) of the search cube.
constexpr double kCellsAcross = 64;

/// One side's search: `bound`, how far the solid may reach; `empty` when no cell may hold it;
/// `settled` unless it stopped at its cell limit (the bound is then the farthest live cell's).
struct SideBound {
    double bound;
    bool empty = false;
    bool settled = true;
};

/// The bounds of the solid within the search cube of half-width `half`: per axis and side, a
/// best-first search that always halves the live cell reaching farthest that way, until that
/// cell is small; nullopt when the solid reaches a face of the cube, the empty box (lo > hi)
/// when no cell may hold it.
std::optional<std::array<AxisRange, 3>> search(const Tape& tape, int axes, double half) {
    std::vector<Interval> ranges;
    auto may_hold_solid = [&](const Cell& c) {
        evaluate_intervals(tape, {Interval{c.lo[0], c.hi[0]}, Interval{c.lo[1], c.hi[1]}, Interval{c.lo[2], c.hi[2]}},
                           ranges);
        return !ranges[tape.root_slot].negative();
    };
    Cell start{};
    for (int a = 0; a < 3; ++a) {
        start.lo[a] = a < axes ? -half : 0.0;
        start.hi[a] = a < axes ? half : 0.0;
    }
    std::array<AxisRange, 3> box;
    if (!may_hold_solid(start)) {
        box[0] = AxisRange{1, -1};
        return box;
    }
    const double small = 2 * half / kCellsAcross / 16;
    auto side_bound = [&](int a, int side, std::size_t max_cells) {
        // How far a cell reaches towards this side (larger: farther).
        auto reach = [&](const Cell& c) { return side == 0 ? -c.lo[a] : c.hi[a]; };
        auto farther = [&](const Cell& p, const Cell& q) { return reach(p) < reach(q); };
        std::priority_queue<Cell, std::vector<Cell>, decltype(farther)> queue(farther);
        queue.push(start);
        std::size_t pops = 0;
        while (!queue.empty()) {
            const Cell c = queue.top();
            queue.pop();
            const bool limit = ++pops > max_cells;
            if (c.hi[0] - c.lo[0] <= small || limit) return SideBound{side == 0 ? c.lo[a] : c.hi[a], false, !limit};
            for (int child = 0; child < (1 << axes); ++child) {
                Cell d = c;
                for (int k = 0; k < axes; ++k) {
                    const double mid = (c.lo[k] + c.hi[k]) / 2;
                    if (child & (1 << k)) d.lo[k] = mid;
                    else d.hi[k] = mid;
                }
                if (may_hold_solid(d)) queue.push(d);
            }
        }
        return SideBound{0.0, true};
    };
    auto at_face = [&](double bound) { return bound <= -half || bound >= half; };
    std::array<SideBound, 6> bounds;   // [2 * axis + side]
    for (int a = 0; a < axes; ++a)
        for (int side = 0; side < 2; ++side) {
            const SideBound& b = bounds[2 * a + side] = side_bound(a, side, kQuickCells);
            if (b.empty) {
                box[0] = AxisRange{1, -1};
                return box;
            }
            if (b.settled && at_face(b.bound)) return std::nullopt;
        }
    for (int a = 0; a < axes; ++a)
        for (int side = 0; side < 2; ++side) {
            SideBound& b = bounds[2 * a + side];
            if (!b.settled) b = side_bound(a, side, kMaxCells);
            if (at_face(b.bound)) return std::nullopt;
            if (side == 0) box[a].min = b.bound;
            else box[a].max = b.bound;
        }
    return box;
}

/// Where intervals are too loose to bound the solid (smooth blends through exp and ln; RANOK's
/// R-operations written out as formulas were, until pruning_tape made them R-operations: the
/// pawn's box is now proved, about [−3.2, 3.2] × [0, 8] × [−3.2, 3.2], not sampled), the
/// nodes of a 65-per-axis lattice over the cube:
/// the box of the positive nodes, one lattice step wider each way; nullopt when a positive
/// node is on the cube's faces (the solid may go on), the empty box when none is positive.
/// Not a proof: a part thinner than a step can lie between the nodes.
std::optional<std::array<AxisRange, 3>> sample(const Model& model, int axes, const std::array<AxisRange, 3>& cube) {
    constexpr int kNodes = 65;
    Grid grid;
    grid.dims = axes == 3 ? 3 : 2;
    Axis* grid_axes[3] = {&grid.x, &grid.y, &grid.z};
    for (int a = 0; a < 3; ++a) *grid_axes[a] = a < axes ? Axis{cube[a].min, cube[a].max, kNodes} : Axis{0, 0, 1};
    const Field field = evaluate_grid(model, grid, default_engine());
    std::array<AxisRange, 3> box;
    for (int a = 0; a < 3; ++a) box[a] = AxisRange{1e300, -1e300};
    bool any = false;
    for (int slice = 0; slice < grid.slices(); ++slice)
        for (int row = 0; row < grid.rows(); ++row)
            for (int col = 0; col < grid.cols(); ++col) {
                if (!(field.values[grid.index(col, row, slice)] > 0)) continue;
                const int at[3] = {col, grid.rows() - 1 - row, slice};
                for (int a = 0; a < axes; ++a) {
                    if (at[a] == 0 || at[a] == kNodes - 1) return std::nullopt;
                    const double x = cube[a].min + at[a] * (*grid_axes[a]).step();
                    box[a].min = std::min(box[a].min, x - grid_axes[a]->step());
                    box[a].max = std::max(box[a].max, x + grid_axes[a]->step());
                }
                any = true;
            }
    if (!any) box[0] = AxisRange{1, -1};
    for (int a = axes; a < 3; ++a) box[a] = AxisRange{-1, 1};
    return box;
}

}  // namespace

std::variant<std::array<AxisRange, 3>, std::string> find_domain_auto(const Model& model) {
    const int axes = static_cast<int>(model.arguments.size());
    const Tape tape = pruning_tape(model.graph, model.root);
    // Growing cubes: far from a model, exp and friends overflow and its intervals say
    // nothing, so the smallest cube whose faces the solid does not reach is the answer.
    bool all_empty = true;
    for (double half = 1; half <= kAutoDomainSearch; half *= 4) {
        const std::optional<std::array<AxisRange, 3>> box = search(tape, axes, half);
        if (!box) { all_empty = false; continue; }
        if ((*box)[0].min > (*box)[0].max) continue;   // nothing in this cube; a larger one may hold it
        return *box;
    }
    // Intervals too loose: growing cubes sampled, then the box found sampled again, finer.
    for (double half = 1; half <= kAutoDomainSearch; half *= 4) {
        std::array<AxisRange, 3> cube;
        for (int a = 0; a < 3; ++a) cube[a] = AxisRange{-half, half};
        const std::optional<std::array<AxisRange, 3>> box = sample(model, axes, cube);
        if (!box) continue;
        if ((*box)[0].min > (*box)[0].max) continue;
        const std::optional<std::array<AxisRange, 3>> finer = sample(model, axes, *box);
        return finer && (*finer)[0].min <= (*finer)[0].max ? *finer : *box;
    }
    const std::string cube = fmt::format("[-{0}, {0}]{1}", kAutoDomainSearch, axes == 3 ? "³" : axes == 2 ? "²" : "");
    if (all_empty)
        return fmt::format("--domain auto: the model is negative everywhere in {} (interval arithmetic): the solid "
                           "is empty; give --domain", cube);
    return fmt::format("--domain auto: the solid reaches the faces of every search cube up to {}: it is unbounded "
                       "(or larger, or its intervals too loose to bound it); give --domain", cube);
}

}  // namespace fortu
