// interp/box_halving.hpp — a box of grid nodes cut in halves along chosen axes: the one split
// the sign renderer and the bricked evaluator both refine with (their boxes differ in type,
// not in shape: lo and hi node indices per axis, both included).
#pragma once

#include <vector>

namespace fortu {

/// `box` halved along every axis a with `halve(a)` true: 2^k parts, low halves first, axes in
/// X, Y, Z order; the low half of [lo, hi] is [lo, mid], the high [mid + 1, hi].
template <class Box, class Halve>
std::vector<Box> halve_axes(const Box& box, Halve halve) {
    std::vector<Box> parts{box};
    for (int a = 0; a < 3; ++a) {
        if (!halve(a)) continue;
        const int mid = (box.lo[a] + box.hi[a]) / 2;
        std::vector<Box> next;
        next.reserve(parts.size() * 2);
        for (const Box& b : parts) {
            Box low = b, high = b;
            low.hi[a] = mid;
            high.lo[a] = mid + 1;
            next.push_back(low);
            next.push_back(high);
        }
        parts = std::move(next);
    }
    return parts;
}

}  // namespace fortu
