// runtime/grid.hpp — the sampling grid of a model (spec §2 "Grid convention").
// Nodes include both ends of every range; image row 0 is the largest Y, column 0 the
// smallest X; slice 0 the smallest Z. Points are stored in image order:
// index = (slice * rows + row) * cols + col.
#pragma once

#include <cstddef>
#include <string>

namespace fortu {

struct Axis {
    double min = -1.0;
    double max = 1.0;
    int nodes = 1;
    /// Distance between neighbouring nodes (0 for a single node).
    double step() const { return nodes > 1 ? (max - min) / (nodes - 1) : 0.0; }
};

struct Grid {
    int dims = 2;          ///< 2 or 3 (a 1-argument model is a 2D grid with one row)
    Axis x, y, z;          ///< z.nodes == 1 for 2D

    int cols() const { return x.nodes; }
    int rows() const { return y.nodes; }
    int slices() const { return dims == 3 ? z.nodes : 1; }
    std::size_t points() const {
        return static_cast<std::size_t>(cols()) * rows() * slices();
    }
    std::size_t index(int col, int row, int slice = 0) const {
        return (static_cast<std::size_t>(slice) * rows() + row) * cols() + col;
    }
    double x_at(int col) const { return x.nodes > 1 ? x.min + col * x.step() : x.min; }
    double y_at(int row) const { return y.nodes > 1 ? y.max - row * y.step() : y.max; }
    double z_at(int slice) const { return z.nodes > 1 ? z.min + slice * z.step() : z.min; }
};

/// Largest number of grid points fortu agrees to allocate (absurd sizes are refused
/// before any allocation).
inline constexpr std::size_t kMaxGridPoints = std::size_t{1} << 28;  // 268M points = 2 GiB of doubles

}  // namespace fortu
