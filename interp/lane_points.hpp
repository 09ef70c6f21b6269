// interp/lane_points.hpp — a tape run at a batch of points, one lane each, in plain doubles or
// in dual numbers (value and exact gradient).
//
// Why: the mesher's leaves, edge solves and refined nodes and the cover pass's Newton probes
// (mesh_cover.hpp) all evaluate scattered points in batches; reading the tape once per batch,
// not once per point, is what makes them cheap, and one binding of lanes to slots serves all.
#pragma once

#include "interp/ir/dual.hpp"
#include "interp/lane_kernel.hpp"
#include "interp/tape.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace fortu {

/// Points `slots` at `width` lanes per slot of `tape` in `lanes` (grown as needed), the zero
/// slot that unused operands read cleared.
template <class T>
void bind_slots(std::vector<T>& lanes, std::vector<T*>& slots, const Tape& tape, int width) {
    if (lanes.size() < std::size_t(tape.slot_count) * width) lanes.assign(std::size_t(tape.slot_count) * width, T(0.0));
    slots.resize(tape.slot_count);
    for (uint32_t s = 0; s < tape.slot_count; ++s) slots[s] = lanes.data() + std::size_t(s) * width;
    std::fill_n(slots[0], width, T(0.0));  // the zero slot unused operands read
}

/// Runs `tape` at `n` points, coordinate(k, axis) of point k (a variable of dual numbers for
/// Dual lanes), in `lanes`; returns the root's lane.
template <class T, class Coordinate>
const T* run_at_points(const Tape& tape, std::vector<T>& lanes, std::vector<T*>& slots, int n, const Coordinate& coordinate) {
    bind_slots(lanes, slots, tape, n);
    for (auto [slot, axis] : tape.arguments)
        for (int k = 0; k < n; ++k) {
            const double x = coordinate(k, int(axis));
            if constexpr (std::is_same_v<T, ir::Dual>) slots[slot][k] = ir::Dual::variable(x, axis);
            else slots[slot][k] = x;
        }
    for (auto [slot, value] : tape.constants) std::fill_n(slots[slot], n, T(value));
    run_lanes<T, 0>(tape.code.data(), tape.code.size(), slots.data(), n);
    return slots[tape.root_slot];
}

}  // namespace fortu
