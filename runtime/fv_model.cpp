// runtime/fv_model.cpp — planes and hyperplanes through the stencil of every node, normalised
// into the FV model's components (fv-method.md §1.1 formula 1.1.3 and §1.2).
#include "runtime/fv_model.hpp"

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

double local_value(std::span<const double> n, double x, double y, double z) {
    assert(n.size() == 4 || n.size() == 5);
    if (n.size() == 4) return -(n[0] * x + n[1] * y + n[3]) / n[2];
    return -(n[0] * x + n[1] * y + n[2] * z + n[4]) / n[3];
}

std::array<double, 5> fv_node(const Field& field, int col, int row, int slice) {
    const Grid& g = field.grid;
    const double x = g.x_at(col), y = g.y_at(row), z = g.z_at(slice);
    const double v = field.values[g.index(col, row, slice)];
    // e_y points to larger Y, which is row − 1 in image order.
    const int cx = neighbour(col, +1, g.cols());
    const int ry = neighbour(row, -1, g.rows());
    const int sz = g.dims == 3 ? neighbour(slice, +1, g.slices()) : -1;
    // A single-node axis gets a virtual neighbour at distance 1 with the node's own value;
    // the normalised plane does not depend on that distance.
    const double vx = cx < 0 ? v : field.values[g.index(cx, row, slice)];
    const double vy = ry < 0 ? v : field.values[g.index(col, ry, slice)];
    const double xx = cx < 0 ? x + 1.0 : g.x_at(cx);
    const double yy = ry < 0 ? y + 1.0 : g.y_at(ry);

    std::array<double, 5> out{};
    if (g.dims != 3) {
        if (!std::isfinite(v) || !std::isfinite(vx) || !std::isfinite(vy)) {
            out.fill(kNaN);
            out[4] = 0.0;
            return out;
        }
        const auto n = fv_plane({x, y, v}, {xx, y, vx}, {x, yy, vy});
        std::copy(n.begin(), n.end(), out.begin());
        return out;
    }
    const double vz = sz < 0 ? v : field.values[g.index(col, row, sz)];
    const double zz = sz < 0 ? z + 1.0 : g.z_at(sz);
    if (!std::isfinite(v) || !std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(vz)) {
        out.fill(kNaN);
        return out;
    }
    return fv_hyperplane({x, y, z, v}, {xx, y, z, vx}, {x, yy, z, vy}, {x, y, zz, vz});
}

FvModel::FvModel(const Field& field) : grid_(field.grid) {
    assert(field.values.size() == grid_.points());
    const int k = components();
    const std::size_t count = nodes();
    data_.resize(k * count);
    for (int s = 0; s < grid_.slices(); ++s)
        for (int r = 0; r < grid_.rows(); ++r)
            for (int c = 0; c < grid_.cols(); ++c) {
                const std::size_t i = grid_.index(c, r, s);
                const auto n = fv_node(field, c, r, s);
                for (int j = 0; j < k; ++j) data_[j * count + i] = n[j];
            }
}

std::span<const double> FvModel::image(int k) const {
    assert(k >= 1 && k <= components());
    return {data_.data() + (k - 1) * nodes(), nodes()};
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
