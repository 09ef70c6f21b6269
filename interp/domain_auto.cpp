// interp/domain_auto.cpp — level-by-level interval subdivision of the search cube.
#include "interp/domain_auto.hpp"

#include "interp/box_simplify.hpp"
#include "interp/interval.hpp"
#include "interp/tape.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <vector>

namespace fortu {
namespace {

struct Cell {
    double lo[3], hi[3];
};

constexpr int kMaxLevels = 40;
constexpr std::size_t kMaxCells = 1 << 16;  ///< stop refining beyond this many live cells
/// Refine until a cell is this fraction of the box found, or finer.
constexpr double kCellsAcross = 64;

double largest_extent(const std::vector<Cell>& live, int axes) {
    double extent = 0;
    for (int a = 0; a < axes; ++a) {
        double lo = 1e300, hi = -1e300;
        for (const Cell& c : live) lo = std::min(lo, c.lo[a]), hi = std::max(hi, c.hi[a]);
        extent = std::max(extent, hi - lo);
    }
    return extent;
}

}  // namespace

std::variant<std::array<AxisRange, 3>, std::string> find_domain_auto(const Model& model) {
    const int axes = static_cast<int>(model.arguments.size());
    const Tape tape = compile_tape(model.graph, TapeSpec{{model.root}, {}, {}, /*reuse_slots=*/false});
    std::vector<Interval> ranges;
    auto may_hold_solid = [&](const Cell& c) {
        evaluate_intervals(tape, {Interval{c.lo[0], c.hi[0]}, Interval{c.lo[1], c.hi[1]}, Interval{c.lo[2], c.hi[2]}},
                           ranges);
        return !ranges[tape.root_slot].negative();
    };
    Cell start{};
    for (int a = 0; a < 3; ++a) {
        start.lo[a] = a < axes ? -kAutoDomainSearch : 0.0;
        start.hi[a] = a < axes ? kAutoDomainSearch : 0.0;
    }
    const std::string cube = fmt::format("[-{0}, {0}]{1}", kAutoDomainSearch, axes == 3 ? "³" : axes == 2 ? "²" : "");
    std::vector<Cell> live;
    if (may_hold_solid(start)) live.push_back(start);
    for (int level = 0; level < kMaxLevels && !live.empty() && live.size() * (1u << axes) <= kMaxCells; ++level) {
        const double cell = live.front().hi[0] - live.front().lo[0];
        if (level > 0 && cell * kCellsAcross <= largest_extent(live, axes)) break;
        std::vector<Cell> next;
        for (const Cell& c : live)
            for (int child = 0; child < (1 << axes); ++child) {
                Cell d = c;
                for (int a = 0; a < axes; ++a) {
                    const double mid = (c.lo[a] + c.hi[a]) / 2;
                    if (child & (1 << a)) d.lo[a] = mid;
                    else d.hi[a] = mid;
                }
                if (may_hold_solid(d)) next.push_back(d);
            }
        live = std::move(next);
    }
    if (live.empty())
        return fmt::format("--domain auto: the model is negative everywhere in the search box {} (interval "
                           "arithmetic): the solid is empty; give --domain", cube);
    std::array<AxisRange, 3> box;
    for (int a = 0; a < axes; ++a) {
        double lo = 1e300, hi = -1e300;
        for (const Cell& c : live) lo = std::min(lo, c.lo[a]), hi = std::max(hi, c.hi[a]);
        if (lo <= -kAutoDomainSearch || hi >= kAutoDomainSearch)
            return fmt::format("--domain auto: the solid reaches the search box {} along {}: it is unbounded (or "
                               "larger, or its intervals too loose to bound it); give --domain", cube,
                               model.arguments[a]);
        box[a] = AxisRange{lo, hi};
    }
    return box;
}

}  // namespace fortu
