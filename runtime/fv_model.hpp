// runtime/fv_model.hpp — the functional-voxel (FV) model of a sampled Field: at every node
// the normalised plane (2D: n1..n4) or hyperplane (3D: n1..n5) through the node and its
// forward neighbours (fv-method.md §1). Its components, palette-encoded, are the M-images.
#pragma once

#include "runtime/bricks.hpp"
#include "runtime/field.hpp"
#include "runtime/grid.hpp"
#include "runtime/parallel.hpp"

#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace fortu {

/// The components of a node of `grid`'s FV model: n + 2 for an n-argument model (n1..n4 in
/// 2D, n1..n5 in 3D).
inline int fv_component_count(const Grid& grid) { return grid.dims == 3 ? 5 : 4; }

/// The normalised plane n1·x + n2·y + n3·z + n4 = 0 through three points {x, y, z}
/// (fv-method.md §1.1, coefficients by formula 1.1.3, divided by the four-term norm
/// √(A²+B²+C²+D²)), oriented so that n3 > 0. All NaN if a coordinate is not finite or
/// the points are collinear (no plane).
std::array<double, 4> fv_plane(const std::array<double, 3>& p1, const std::array<double, 3>& p2,
                               const std::array<double, 3>& p3);

/// The normalised hyperplane n1·x + n2·y + n3·z + n4·u + n5 = 0 through four points
/// {x, y, z, u} (fv-method.md §1.2: cofactor expansion a_x = +M1, a_y = −M2, a_z = +M3,
/// a_u = −M4, a_0 = +M5, five-term norm), oriented so that n4 > 0 — the coefficient of the
/// function value is positive, as n3 is in 2D. All NaN if a coordinate is not finite or the
/// points are degenerate.
std::array<double, 5> fv_hyperplane(const std::array<double, 4>& p0, const std::array<double, 4>& p1,
                                    const std::array<double, 4>& p2, const std::array<double, 4>& p3);

/// The local function of one node: 4 components → z = −(n1·x + n2·y + n4)/n3 (fv-method.md
/// §1.1 item 6); 5 components → u = −(n1·x + n2·y + n3·z + n5)/n4 (§1.2). `z` is ignored
/// in 2D. NaN for an invalid node.
/// Inline: the fv engine reads every operand of every operation through it.
inline double local_value(std::span<const double> n, double x, double y, double z = 0.0) {
    if (n.size() == 4) return -(n[0] * x + n[1] * y + n[3]) / n[2];
    return -(n[0] * x + n[1] * y + n[2] * z + n[4]) / n[3];
}

/// The components of one node of `field`: n1..n4 in 2D (the 5th entry is 0), n1..n5 in 3D.
/// The stencil is the triangle p, p+e_x, p+e_y (3D: the tetrahedron p, p+e_x, p+e_y, p+e_z)
/// in world coordinates, e_y pointing to larger Y (row − 1 in image order). At the last
/// column / top row / last slice the backward neighbour is used instead. An axis with a
/// single node (a 1-argument model) gets a virtual neighbour one unit away carrying the
/// node's own value, i.e. the function is taken as constant along that axis. All NaN where
/// any stencil value is not finite (an invalid point).
std::array<double, 5> fv_node(const Field& field, int col, int row, int slice = 0);

/// fv_node() for whole rows: the coordinates, neighbours and steps of every axis computed
/// once, so a node costs its plane alone. What FvModel and the M-image writers use.
class FvStencil {
public:
    explicit FvStencil(const Grid& grid);
    /// The components of every node of one row: n_k of column c into out[k-1][c]
    /// (k = 1..4 in 2D, 1..5 in 3D). `field` is on the grid given to the constructor.
    void row(const Field& field, int row, int slice, double* const* out) const;

    /// The nodes whose values the stencils of `own`'s nodes read: `own` and one node more on
    /// each axis's forward side where the grid has one (the backward neighbour, inside the
    /// grid, at its last column / top row / last slice).
    BrickBox reach(const BrickBox& own) const;
    /// The components of the nodes of `own` from the values of the box `held` (BrickBox::local
    /// order; `held` contains reach(own)): n_k of a node into out[k-1][own.local(...)]. The
    /// whole grid's coordinates and neighbours, only offset, and the same arithmetic as
    /// row(): a brick's components equal the whole field's bit for bit.
    void box(const double* values, const BrickBox& held, const BrickBox& own, double* const* out) const;
    int components() const { return fv_component_count(grid_); }

private:
    /// Columns col_lo..col_hi of one row: here[c - x0], up[c - x0], front[c - x0] are the
    /// values at column c of the row, of its Y neighbour row and of its Z neighbour slice.
    void span(const double* here, const double* up, const double* front, int x0, int row, int slice, int col_lo,
              int col_hi, double* const* out, std::size_t at) const;

    Grid grid_;
    std::vector<double> coord_[3], step_[3];
    std::vector<int> next_[3];
};

/// The components of every row of one slice, computed on all cores: visit(row, n) gets
/// n[k][c] = n_{k+1} of column c, valid during the call (per-thread scratch). What the
/// M-image writers stream from.
template <class Visit>
void for_each_fv_row(const Field& field, int slice, Visit&& visit) {
    const Grid& g = field.grid;
    const std::size_t components = static_cast<std::size_t>(fv_component_count(g)), cols = static_cast<std::size_t>(g.cols());
    const std::size_t rows = static_cast<std::size_t>(g.rows());
    const FvStencil stencil(g);
    std::vector<std::vector<double>> scratch(static_cast<std::size_t>(worker_count(rows, 0)),
                                             std::vector<double>(components * cols));
    parallel_for(rows, 0, nullptr, [&](std::size_t r, int worker) {
        double* n[5];
        for (std::size_t k = 0; k < components; ++k) n[k] = scratch[worker].data() + k * cols;
        stencil.row(field, static_cast<int>(r), slice, n);
        visit(r, static_cast<const double* const*>(n));
    });
}

/// The FV model of a whole Field. Components are stored as double, one contiguous array per
/// component (one array = one M-image before palette encoding): fv-method.md §1.1 item 7
/// recommends float or double internally, and double keeps the local function exact at the
/// stencil vertices (~1e-13) instead of float's ~1e-7. Memory: (dims+2)·8 bytes per node;
/// writers that stream large 3D grids call fv_node() per slice instead.
class FvModel {
public:
    /// Computed on all cores, a row per work item.
    explicit FvModel(const Field& field);

    const Grid& grid() const { return grid_; }
    /// n + 2 for an n-argument model: 4 in 2D, 5 in 3D.
    int components() const { return fv_component_count(grid_); }
    std::size_t nodes() const { return grid_.points(); }

    /// Component n_k (k = 1..components(), as in the spec's n1..n5) of a node in image order.
    double n(int k, std::size_t node) const { return data_[(k - 1) * nodes() + node]; }
    /// The whole k-th normalised M-image (k = 1..components()), in image order.
    std::span<const double> image(int k) const;
    /// The components n1..n_{components()} of one node.
    std::array<double, 5> node(std::size_t node) const;
    /// The value of the node's local function at world point (x, y[, z]).
    double local_value(std::size_t node, double x, double y, double z = 0.0) const;

private:
    Grid grid_;
    std::unique_ptr<double[]> data_;   ///< components() arrays of nodes() values
};

}  // namespace fortu
