// runtime/fv_model.cpp — planes and hyperplanes through the stencil of every node, normalised
// into the FV model's components (fv-method.md §1.1 formula 1.1.3 and §1.2).
#include "runtime/fv_model.hpp"

#include "runtime/parallel.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace fortu {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Divides the coefficients by their Euclidean norm (fv-method.md §1.1 item 4: the free term is
// part of the norm) and flips all of them if the coefficient of the function value, c[value_at],
// is negative. Scaling by the largest magnitude first keeps the squares from overflowing or
// underflowing. No plane (all zero) or a non-finite coefficient gives all NaN.
template <std::size_t N>
std::array<double, N> normalise(std::array<double, N> c, std::size_t value_at) {
    double scale = 0.0;
    for (double v : c) scale = std::max(scale, std::abs(v));
    if (!(scale > 0.0) || !std::isfinite(scale)) {
        c.fill(kNaN);
        return c;
    }
    double sum = 0.0;
    for (double& v : c) {
        v /= scale;
        sum += v * v;
    }
    const double norm = c[value_at] < 0.0 ? -std::sqrt(sum) : std::sqrt(sum);
    for (double& v : c) v /= norm;
    return c;
}

// normalise() with one square root and one division: exact to an ulp or two, and three times
// faster than scaling first; the careful path only where the squares could leave double's range.
template <std::size_t N>
std::array<double, N> normalise_fast(std::array<double, N> c, std::size_t value_at) {
    double sum = 0.0;
    for (double v : c) sum += v * v;
    if (!(sum > 1e-280 && sum < 1e280)) return normalise<N>(c, value_at);
    const double inverse = (c[value_at] < 0.0 ? -1.0 : 1.0) / std::sqrt(sum);
    for (double& v : c) v *= inverse;
    return c;
}

// 4×4 determinant by Laplace expansion along the first two rows (2×2 minors).
double det4(const std::array<std::array<double, 4>, 4>& m) {
    const double s0 = m[0][0] * m[1][1] - m[1][0] * m[0][1];
    const double s1 = m[0][0] * m[1][2] - m[1][0] * m[0][2];
    const double s2 = m[0][0] * m[1][3] - m[1][0] * m[0][3];
    const double s3 = m[0][1] * m[1][2] - m[1][1] * m[0][2];
    const double s4 = m[0][1] * m[1][3] - m[1][1] * m[0][3];
    const double s5 = m[0][2] * m[1][3] - m[1][2] * m[0][3];
    const double c5 = m[2][2] * m[3][3] - m[3][2] * m[2][3];
    const double c4 = m[2][1] * m[3][3] - m[3][1] * m[2][3];
    const double c3 = m[2][1] * m[3][2] - m[3][1] * m[2][2];
    const double c2 = m[2][0] * m[3][3] - m[3][0] * m[2][3];
    const double c1 = m[2][0] * m[3][2] - m[3][0] * m[2][2];
    const double c0 = m[2][0] * m[3][1] - m[3][0] * m[2][1];
    return s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
}

// The stencil neighbour of `i` along an axis of `nodes` nodes: forward (i + step) if it exists,
// else backward; −1 for a single-node axis.
int neighbour(int i, int step, int nodes) {
    if (nodes <= 1) return -1;
    const int forward = i + step;
    return forward >= 0 && forward < nodes ? forward : i - step;
}

}  // namespace

std::array<double, 4> fv_plane(const std::array<double, 3>& p1, const std::array<double, 3>& p2,
                               const std::array<double, 3>& p3) {
    const auto [X1, Y1, Z1] = p1;
    const auto [X2, Y2, Z2] = p2;
    const auto [X3, Y3, Z3] = p3;
    // fv-method.md §1.1 formula 1.1.3, the 4×4 determinant expanded along its first row.
    const double A = Y1 * (Z2 - Z3) - Y2 * (Z1 - Z3) + Y3 * (Z1 - Z2);
    const double B = -(X1 * (Z2 - Z3) - X2 * (Z1 - Z3) + X3 * (Z1 - Z2));
    const double C = X1 * (Y2 - Y3) - X2 * (Y1 - Y3) + X3 * (Y1 - Y2);
    const double D = -(X1 * (Y2 * Z3 - Y3 * Z2) - X2 * (Y1 * Z3 - Y3 * Z1) + X3 * (Y1 * Z2 - Y2 * Z1));
    return normalise<4>({A, B, C, D}, 2);
}

std::array<double, 5> fv_hyperplane(const std::array<double, 4>& p0, const std::array<double, 4>& p1,
                                    const std::array<double, 4>& p2, const std::array<double, 4>& p3) {
    // fv-method.md §1.2: det[[x, y, z, u, 1]; [Xk, Yk, Zk, Uk, 1]] = 0 expanded along its first
    // row; M_j is the 4×4 minor of the vertex rows with column j deleted.
    const std::array<std::array<double, 5>, 4> rows{{{p0[0], p0[1], p0[2], p0[3], 1.0},
                                                     {p1[0], p1[1], p1[2], p1[3], 1.0},
                                                     {p2[0], p2[1], p2[2], p2[3], 1.0},
                                                     {p3[0], p3[1], p3[2], p3[3], 1.0}}};
    auto minor = [&rows](int deleted) {
        std::array<std::array<double, 4>, 4> m{};
        for (int r = 0; r < 4; ++r)
            for (int c = 0, k = 0; c < 5; ++c)
                if (c != deleted) m[r][k++] = rows[r][c];
        return det4(m);
    };
    return normalise<5>({minor(0), -minor(1), minor(2), -minor(3), minor(4)}, 3);
}

namespace {

// The stencil's edges run along the axes, so the plane of formula 1.1.3 (§1.2's hyperplane)
// has the cross product of the edge vectors as its normal: in 2D (hx, 0, Δx) × (0, hy, Δy) =
// (−Δx·hy, −hx·Δy, hx·hy). The same plane as fv_plane() (the test checks it to 1e-14), at a
// third of the cost, and its free term has no cancellation between products of coordinates.
inline void stencil_plane(double x, double y, double v, double hx, double hy, double vx, double vy, double* n) {
    if (!std::isfinite(v) || !std::isfinite(vx) || !std::isfinite(vy)) {
        std::fill_n(n, 4, kNaN);
        return;
    }
    const double A = -(vx - v) * hy, B = -hx * (vy - v), C = hx * hy;
    const auto r = normalise_fast<4>({A, B, C, -(A * x + B * y + C * v)}, 2);
    std::copy(r.begin(), r.end(), n);
}

// 4D: the normal of the edges (hx,0,0,Δx), (0,hy,0,Δy), (0,0,hz,Δz).
inline void stencil_hyperplane(const double p[4], const double h[3], double vx, double vy, double vz, double* n) {
    const double v = p[3];
    if (!std::isfinite(v) || !std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(vz)) {
        std::fill_n(n, 5, kNaN);
        return;
    }
    const double A = -(vx - v) * h[1] * h[2], B = -h[0] * (vy - v) * h[2], C = -h[0] * h[1] * (vz - v),
                 U = h[0] * h[1] * h[2];
    const auto r = normalise_fast<5>({A, B, C, U, -(A * p[0] + B * p[1] + C * p[2] + U * v)}, 3);
    std::copy(r.begin(), r.end(), n);
}

}  // namespace

FvStencil::FvStencil(const Grid& grid) : grid_(grid) {
    const int steps[3] = {+1, -1, +1};   // e_y points to larger Y: row − 1 in image order
    for (int a = 0; a < 3; ++a) {
        const int nodes = a == 0 ? grid.cols() : a == 1 ? grid.rows() : grid.slices();
        auto at = [&](int i) { return a == 0 ? grid.x_at(i) : a == 1 ? grid.y_at(i) : grid.z_at(i); };
        coord_[a].resize(nodes);
        step_[a].resize(nodes);
        next_[a].resize(nodes);
        for (int i = 0; i < nodes; ++i) {
            const int j = neighbour(i, steps[a], nodes);
            coord_[a][i] = at(i);
            // A single-node axis gets a virtual neighbour at distance 1 with the node's own
            // value; the normalised plane does not depend on that distance.
            step_[a][i] = j < 0 ? 1.0 : at(j) - at(i);
            next_[a][i] = j < 0 ? i : j;
        }
    }
}

void FvStencil::span(const double* here, const double* up, const double* front, int x0, int row, int slice,
                     int col_lo, int col_hi, double* const* out, std::size_t at) const {
    const double y = coord_[1][row], hy = step_[1][row];
    if (grid_.dims != 3) {
        for (int c = col_lo; c <= col_hi; ++c, ++at) {
            double n[4];
            stencil_plane(coord_[0][c], y, here[c - x0], step_[0][c], hy, here[next_[0][c] - x0], up[c - x0], n);
            for (int k = 0; k < 4; ++k) out[k][at] = n[k];
        }
        return;
    }
    for (int c = col_lo; c <= col_hi; ++c, ++at) {
        const double p[4] = {coord_[0][c], y, coord_[2][slice], here[c - x0]};
        const double h[3] = {step_[0][c], hy, step_[2][slice]};
        double n[5];
        stencil_hyperplane(p, h, here[next_[0][c] - x0], up[c - x0], front[c - x0], n);
        for (int k = 0; k < 5; ++k) out[k][at] = n[k];
    }
}

void FvStencil::row(const Field& field, int row, int slice, double* const* out) const {
    const Grid& g = grid_;
    const double* values = field.values.data();
    const double* here = values + g.index(0, row, slice);
    const double* up = values + g.index(0, next_[1][row], slice);
    const double* front = g.dims == 3 ? values + g.index(0, row, next_[2][slice]) : here;
    span(here, up, front, 0, row, slice, 0, g.cols() - 1, out, 0);
}

BrickBox FvStencil::reach(const BrickBox& own) const {
    BrickBox held = own;
    for (int a = 0; a < 3; ++a) {
        // Stencils read i and next(i); next is i ± 1, so the ends of the range decide.
        const int lo = next_[a][own.lo[a]], hi = next_[a][own.hi[a]];
        held.lo[a] = std::min({own.lo[a], lo, hi});
        held.hi[a] = std::max({own.hi[a], lo, hi});
    }
    return held;
}

void FvStencil::box(const double* values, const BrickBox& held, const BrickBox& own, double* const* out) const {
    assert(held.lo[0] <= own.lo[0] && held.hi[0] >= own.hi[0]);
    for (int s = own.lo[2]; s <= own.hi[2]; ++s)
        for (int r = own.lo[1]; r <= own.hi[1]; ++r) {
            const double* here = values + held.local(held.lo[0], r, s);
            const double* up = values + held.local(held.lo[0], next_[1][r], s);
            const double* front = grid_.dims == 3 ? values + held.local(held.lo[0], r, next_[2][s]) : here;
            span(here, up, front, held.lo[0], r, s, own.lo[0], own.hi[0], out, own.local(own.lo[0], r, s));
        }
}

std::array<double, 5> fv_node(const Field& field, int col, int row, int slice) {
    const Grid& g = field.grid;
    const double x = g.x_at(col), y = g.y_at(row), z = g.z_at(slice);
    const double v = field.values[g.index(col, row, slice)];
    const int cx = neighbour(col, +1, g.cols());
    const int ry = neighbour(row, -1, g.rows());
    const int sz = g.dims == 3 ? neighbour(slice, +1, g.slices()) : -1;
    const double vx = cx < 0 ? v : field.values[g.index(cx, row, slice)];
    const double vy = ry < 0 ? v : field.values[g.index(col, ry, slice)];
    const double hx = cx < 0 ? 1.0 : g.x_at(cx) - x;
    const double hy = ry < 0 ? 1.0 : g.y_at(ry) - y;
    std::array<double, 5> out{};
    if (g.dims != 3) {
        stencil_plane(x, y, v, hx, hy, vx, vy, out.data());
        return out;
    }
    const double vz = sz < 0 ? v : field.values[g.index(col, row, sz)];
    const double p[4] = {x, y, z, v};
    const double h[3] = {hx, hy, sz < 0 ? 1.0 : g.z_at(sz) - z};
    stencil_hyperplane(p, h, vx, vy, vz, out.data());
    return out;
}

FvModel::FvModel(const Field& field) : grid_(field.grid) {
    assert(field.values.size() == grid_.points());
    const int k = components();
    const std::size_t count = nodes();
    // Not zeroed: every entry is written below, first by the thread that computes it (the
    // page faults of 4 × 8 bytes per node were half the time on one thread).
    data_.reset(new double[k * count]);
    const FvStencil stencil(grid_);
    const std::size_t lines = static_cast<std::size_t>(grid_.rows()) * grid_.slices();
    parallel_for(lines, 0, nullptr, [&](std::size_t line, int) {
        const int r = static_cast<int>(line % grid_.rows()), s = static_cast<int>(line / grid_.rows());
        double* out[5];
        for (int j = 0; j < k; ++j) out[j] = data_.get() + j * count + grid_.index(0, r, s);
        stencil.row(field, r, s, out);
    });
}

std::span<const double> FvModel::image(int k) const {
    assert(k >= 1 && k <= components());
    return {data_.get() + (k - 1) * nodes(), nodes()};
}

std::array<double, 5> FvModel::node(std::size_t node) const {
    std::array<double, 5> out{};
    for (int k = 1; k <= components(); ++k) out[k - 1] = n(k, node);
    return out;
}

double FvModel::local_value(std::size_t node, double x, double y, double z) const {
    const auto n = this->node(node);
    return fortu::local_value(std::span<const double>(n.data(), components()), x, y, z);
}

}  // namespace fortu
