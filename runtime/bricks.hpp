// runtime/bricks.hpp — a grid cut into bricks (the unit of out-of-core, resumable and
// distributed runs): boxes of grid nodes numbered x fastest, then rows, then slices.
#pragma once

#include "runtime/grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
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

/// The grid cut into bricks of `shape` nodes per axis (the last ones smaller).
struct BrickLayout {
    Grid grid;
    std::array<int, 3> shape{};    ///< nodes per brick along each axis
    std::array<int, 3> counts{};   ///< bricks per axis

    /// Cubes of `edge` nodes per axis: a sparse writer keeps each brick's band, and
    /// compact boxes let intervals decide the most.
    BrickLayout(const Grid& g, int edge) : BrickLayout(g, std::array<int, 3>{edge, edge, edge}) {}

    /// Bricks of about edge³ nodes made of whole grid rows (all columns, a square of rows
    /// and slices): in a dense file (volume order) each slice of such a brick is one
    /// contiguous run, so a brick is a few large writes and no file page is shared by
    /// the bricks of one row (a cube's 1 KiB row pieces made every page four writes,
    /// each written back on its own).
    static BrickLayout whole_rows(const Grid& g, int edge) {
        const double per_row = std::max(1.0, double(edge) * edge * edge / g.cols());
        const int rows = std::clamp(int(std::sqrt(per_row)), 1, g.rows());
        const int slices = std::clamp(int(per_row / rows), 1, g.slices());
        return BrickLayout(g, std::array<int, 3>{g.cols(), rows, slices});
    }

    BrickLayout(const Grid& g, std::array<int, 3> brick_shape) : grid(g), shape(brick_shape) {
        const int nodes[3] = {g.cols(), g.rows(), g.slices()};
        for (int a = 0; a < 3; ++a) counts[a] = (nodes[a] + shape[a] - 1) / shape[a];
    }
    std::size_t size() const { return std::size_t(counts[0]) * counts[1] * counts[2]; }
    /// Nodes of the largest brick.
    std::size_t brick_points() const {
        const int nodes[3] = {grid.cols(), grid.rows(), grid.slices()};
        std::size_t n = 1;
        for (int a = 0; a < 3; ++a) n *= std::size_t(std::min(shape[a], nodes[a]));
        return n;
    }
    BrickBox box(std::size_t index) const {
        const int nodes[3] = {grid.cols(), grid.rows(), grid.slices()};
        const int at[3] = {int(index % counts[0]), int(index / counts[0] % counts[1]),
                           int(index / counts[0] / counts[1])};
        BrickBox b;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = at[a] * shape[a];
            b.hi[a] = std::min(nodes[a], b.lo[a] + shape[a]) - 1;
        }
        return b;
    }
};

}  // namespace fortu
