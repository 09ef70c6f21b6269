// runtime/bricks.hpp — a grid cut into bricks (the unit of out-of-core, resumable and
// distributed runs): boxes of grid nodes numbered x fastest, then rows, then slices.
#pragma once

#include "runtime/grid.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace fortu {

/// A box of grid nodes: inclusive index ranges per axis (col, row, slice).
struct BrickBox {
    std::array<int, 3> lo{};
    std::array<int, 3> hi{};
    std::array<int, 3> extent() const { return {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1}; }
    std::size_t points() const {
        const std::array<int, 3> e = extent();
        return std::size_t(e[0]) * e[1] * e[2];
    }
    /// Index of node (col, row, slice) in a brick's values (grid order local to the box).
    std::size_t local(int col, int row, int slice) const {
        const std::array<int, 3> e = extent();
        return (std::size_t(slice - lo[2]) * e[1] + (row - lo[1])) * e[0] + (col - lo[0]);
    }
};

/// The grid cut into bricks of `edge` nodes per axis (the last ones smaller).
struct BrickLayout {
    Grid grid;
    int edge = 128;
    std::array<int, 3> counts{};   ///< bricks per axis

    BrickLayout(const Grid& g, int brick_edge) : grid(g), edge(brick_edge) {
        const int nodes[3] = {g.cols(), g.rows(), g.slices()};
        for (int a = 0; a < 3; ++a) counts[a] = (nodes[a] + edge - 1) / edge;
    }
    std::size_t size() const { return std::size_t(counts[0]) * counts[1] * counts[2]; }
    BrickBox box(std::size_t index) const {
        const int nodes[3] = {grid.cols(), grid.rows(), grid.slices()};
        const int at[3] = {int(index % counts[0]), int(index / counts[0] % counts[1]),
                           int(index / counts[0] / counts[1])};
        BrickBox b;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = at[a] * edge;
            b.hi[a] = std::min(nodes[a], b.lo[a] + edge) - 1;
        }
        return b;
    }
};

}  // namespace fortu
