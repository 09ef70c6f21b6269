// interp/segment_through_triangle.hpp — whether a segment passes through a triangle: the one
// test the passes that must not add crossing triangles (mesh_features, mesh_cover) share.
//
// Why one: the feature pass checks triangles of one cell against each other, where a segment
// ending on another triangle's plane is a shared corner's, not a crossing; the cover pass
// checks a new vertex's triangles against any near it, where such an end may be a real
// touch, and refusing it is the safe side. Both are the same orientation test.
#pragma once

#include <array>

namespace fortu {

/// How a segment with exactly one end on the triangle's plane (within eps) counts.
enum class EndOnPlane { misses, crosses };

/// Whether segment pq passes through the inside of triangle abc, orientations taken beyond
/// `eps` of volume. A segment in the triangle's plane never does (the shared-edge fold tests
/// see those).
inline bool segment_through_triangle(const std::array<double, 3>& p, const std::array<double, 3>& q,
                                     const std::array<double, 3>& a, const std::array<double, 3>& b,
                                     const std::array<double, 3>& c, double eps, EndOnPlane end) {
    using V = std::array<double, 3>;
    auto orient = [eps](const V& w, const V& x, const V& y, const V& z) {
        const V u{x[0] - w[0], x[1] - w[1], x[2] - w[2]}, s{y[0] - w[0], y[1] - w[1], y[2] - w[2]},
            t{z[0] - w[0], z[1] - w[1], z[2] - w[2]};
        const double v = u[0] * (s[1] * t[2] - s[2] * t[1]) + u[1] * (s[2] * t[0] - s[0] * t[2]) + u[2] * (s[0] * t[1] - s[1] * t[0]);
        return v > eps ? 1 : v < -eps ? -1 : 0;
    };
    const int s1 = orient(a, b, c, p), s2 = orient(a, b, c, q);
    if (s1 * s2 > 0 || (s1 == 0 && s2 == 0)) return false;
    if (s1 * s2 == 0 && end == EndOnPlane::misses) return false;
    const int u = orient(p, q, a, b), v = orient(p, q, b, c), w = orient(p, q, c, a);
    return (u >= 0 && v >= 0 && w >= 0) || (u <= 0 && v <= 0 && w <= 0);
}

}  // namespace fortu
