// interp/ir/dual.hpp — forward-mode automatic differentiation over the IR kernels.
// `fortu eval` reports the exact gradient of the model at a point: evaluating the same
// kernels with Dual instead of double carries d/dX, d/dY, d/dZ along, in either engine,
// at the cost of one evaluation (finite differences would need 2·dims more, which matters
// for the classic engine on models like Bone.fortu at ~4·10⁸ operations per point).
#pragma once

#include <cmath>
#include <limits>

namespace fortu::ir {

struct Dual {
    double v = 0.0;
    double d[3] = {0.0, 0.0, 0.0};

    Dual() = default;
    Dual(double value) : v(value) {}  // NOLINT: constants convert implicitly
    static Dual variable(double value, int axis) {
        Dual x(value);
        x.d[axis] = 1.0;
        return x;
    }
};

/// Applies the chain rule: result value `value`, derivative `slope` times a's derivative.
inline Dual chain(const Dual& a, double value, double slope) {
    Dual r(value);
    for (int i = 0; i < 3; ++i) r.d[i] = slope * a.d[i];
    return r;
}

inline Dual operator-(const Dual& a) { return chain(a, -a.v, -1.0); }
inline Dual operator+(const Dual& a, const Dual& b) {
    Dual r(a.v + b.v);
    for (int i = 0; i < 3; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
}
inline Dual operator-(const Dual& a, const Dual& b) {
    Dual r(a.v - b.v);
    for (int i = 0; i < 3; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
}
inline Dual operator*(const Dual& a, const Dual& b) {
    Dual r(a.v * b.v);
    for (int i = 0; i < 3; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
}
inline Dual operator/(const Dual& a, const Dual& b) {
    Dual r(a.v / b.v);
    for (int i = 0; i < 3; ++i) r.d[i] = (a.d[i] * b.v - a.v * b.d[i]) / (b.v * b.v);
    return r;
}
inline bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
inline bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
inline bool operator!=(const Dual& a, const Dual& b) { return a.v != b.v; }

}  // namespace fortu::ir
