// interp/quadrant_intervals.hpp — the intervals of a 2D box's four quadrants in one walk of
// the box's shortened tape, a quadrant per vector lane.
//
// Why: the quadtree evaluates every undecided box's four quadrants on the same tape. One
// walk for the four pays the tape's per-instruction cost — the dispatch on the operation,
// mispredicted on prospero.vm's random mix, and the reading of its 56-byte instructions —
// once instead of four times, and the arithmetic runs on four lanes at once. The rules are
// box_intervals.hpp's (interval.cpp's on finite operands, the same IEEE operations in the
// same order per lane; interval_op per lane for the rest), so every lane's ranges and
// choice bytes equal evaluate_box_intervals' for its quadrant, bit for bit.
#pragma once

#include "interp/interval.hpp"
#include "interp/tape.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace fortu {

/// Working memory of evaluate_quadrant_intervals, reused from box to box.
struct QuadrantScratch {
    struct alignas(32) Ranges {
        double lo[4];
        double hi[4];
    };
    std::vector<Ranges> ranges;     ///< per slot: the four quadrants' bounds
    std::vector<uint8_t> maybe_nan; ///< per slot: bit q set when quadrant q's range may be NaN
};

/// For each quadrant q (coordinate ranges `axes[q]`): `choices[q]` as
/// evaluate_box_intervals gives them for that box, and `roots[q]`, its root's range.
void evaluate_quadrant_intervals(const Tape& tape, const std::array<std::array<Interval, 3>, 4>& axes,
                                 QuadrantScratch& scratch, std::array<std::vector<uint8_t>, 4>& choices,
                                 std::array<Interval, 4>& roots);

}  // namespace fortu
