// interp/ir/kernels.hpp — the scalar semantics of every IR operation, written once and
// shared by the constant folder, the classic walker, the voxel tiles and gradients
// (house style rule 5: engines share kernels, not loops). Each k_* has a double overload
// (what the engines run) and a Dual overload (exact gradients, dual.hpp).
#pragma once

#include "interp/ir/dual.hpp"

#include <cmath>
#include <concepts>
#include <limits>
#include <type_traits>

namespace fortu::ir {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- double and float (float: the voxel engine's float32 mode, the same formulas) ----
template <std::floating_point F> inline F k_sqrt(F a) { return std::sqrt(a); }
template <std::floating_point F> inline F k_abs(F a) { return std::fabs(a); }
template <std::floating_point F> inline F k_exp(F a) { return std::exp(a); }
template <std::floating_point F> inline F k_log(F a) { return std::log(a); }
template <std::floating_point F> inline F k_log10(F a) { return std::log10(a); }
template <std::floating_point F> inline F k_log2(F a) { return std::log2(a); }
template <std::floating_point F> inline F k_sin(F a) { return std::sin(a); }
template <std::floating_point F> inline F k_cos(F a) { return std::cos(a); }
template <std::floating_point F> inline F k_tan(F a) { return std::tan(a); }
template <std::floating_point F> inline F k_asin(F a) { return std::asin(a); }
template <std::floating_point F> inline F k_acos(F a) { return std::acos(a); }
template <std::floating_point F> inline F k_atan(F a) { return std::atan(a); }
template <std::floating_point F> inline F k_atan2(F a, F b) { return std::atan2(a, b); }
template <std::floating_point F> inline F k_sinh(F a) { return std::sinh(a); }
template <std::floating_point F> inline F k_cosh(F a) { return std::cosh(a); }
template <std::floating_point F> inline F k_tanh(F a) { return std::tanh(a); }
template <std::floating_point F> inline F k_sign(F a) { return a > 0 ? F(1) : a < 0 ? F(-1) : a; }  // keeps NaN, ±0
template <std::floating_point F> inline F k_floor(F a) { return std::floor(a); }
template <std::floating_point F> inline F k_ceil(F a) { return std::ceil(a); }
template <std::floating_point F> inline F k_mod(F a, F b) { return std::fmod(a, b); }
template <std::floating_point F> inline F k_hypot(F a, F b) { return std::hypot(a, b); }
template <std::floating_point F> inline F k_pow(F a, F b) { return std::pow(a, b); }
// min/max propagate NaN from either side (an invalid operand makes an invalid point),
// unlike std::fmin; written without branches on the value so loops vectorise.
template <std::floating_point F> inline F k_min(F a, F b) { return (a < b || a != a) ? a : b; }
template <std::floating_point F> inline F k_max(F a, F b) { return (a > b || a != a) ? a : b; }
template <std::floating_point F> inline F k_select(F c, F a, F b) { return c > 0 ? a : (c != c ? c : b); }

// ---- Dual (forward-mode derivatives) ----
inline Dual k_sqrt(const Dual& a) { double s = std::sqrt(a.v); return chain(a, s, 0.5 / s); }
inline Dual k_abs(const Dual& a) { return chain(a, std::fabs(a.v), a.v < 0 ? -1.0 : 1.0); }
inline Dual k_exp(const Dual& a) { double e = std::exp(a.v); return chain(a, e, e); }
inline Dual k_log(const Dual& a) { return chain(a, std::log(a.v), 1.0 / a.v); }
inline Dual k_log10(const Dual& a) { return chain(a, std::log10(a.v), 1.0 / (a.v * std::log(10.0))); }
inline Dual k_log2(const Dual& a) { return chain(a, std::log2(a.v), 1.0 / (a.v * std::log(2.0))); }
inline Dual k_sin(const Dual& a) { return chain(a, std::sin(a.v), std::cos(a.v)); }
inline Dual k_cos(const Dual& a) { return chain(a, std::cos(a.v), -std::sin(a.v)); }
inline Dual k_tan(const Dual& a) { double t = std::tan(a.v); return chain(a, t, 1.0 + t * t); }
inline Dual k_asin(const Dual& a) { return chain(a, std::asin(a.v), 1.0 / std::sqrt(1.0 - a.v * a.v)); }
inline Dual k_acos(const Dual& a) { return chain(a, std::acos(a.v), -1.0 / std::sqrt(1.0 - a.v * a.v)); }
inline Dual k_atan(const Dual& a) { return chain(a, std::atan(a.v), 1.0 / (1.0 + a.v * a.v)); }
inline Dual k_atan2(const Dual& y, const Dual& x) {
    Dual r(std::atan2(y.v, x.v));
    double q = x.v * x.v + y.v * y.v;
    for (int i = 0; i < 3; ++i) r.d[i] = (x.v * y.d[i] - y.v * x.d[i]) / q;
    return r;
}
inline Dual k_sinh(const Dual& a) { return chain(a, std::sinh(a.v), std::cosh(a.v)); }
inline Dual k_cosh(const Dual& a) { return chain(a, std::cosh(a.v), std::sinh(a.v)); }
inline Dual k_tanh(const Dual& a) { double t = std::tanh(a.v); return chain(a, t, 1.0 - t * t); }
inline Dual k_sign(const Dual& a) { return Dual(k_sign(a.v)); }
inline Dual k_floor(const Dual& a) { return Dual(std::floor(a.v)); }
inline Dual k_ceil(const Dual& a) { return Dual(std::ceil(a.v)); }
inline Dual k_mod(const Dual& a, const Dual& b) { return a - Dual(std::trunc(a.v / b.v)) * b; }
inline Dual k_hypot(const Dual& a, const Dual& b) {
    Dual r(std::hypot(a.v, b.v));
    for (int i = 0; i < 3; ++i) r.d[i] = (a.v * a.d[i] + b.v * b.d[i]) / r.v;
    return r;
}
inline Dual k_pow(const Dual& a, const Dual& b) {
    Dual r(std::pow(a.v, b.v));
    // d(a^b) = b a^(b-1) da + a^b ln(a) db; the ln term only where b varies.
    double da = b.v * std::pow(a.v, b.v - 1.0);
    double db = (b.d[0] != 0 || b.d[1] != 0 || b.d[2] != 0) ? r.v * std::log(a.v) : 0.0;
    for (int i = 0; i < 3; ++i) r.d[i] = da * a.d[i] + db * b.d[i];
    return r;
}
inline Dual k_min(const Dual& a, const Dual& b) { return (a.v < b.v || a.v != a.v) ? a : b; }
inline Dual k_max(const Dual& a, const Dual& b) { return (a.v > b.v || a.v != a.v) ? a : b; }
inline Dual k_select(const Dual& c, const Dual& a, const Dual& b) {
    return c.v > 0 ? a : (c.v != c.v ? Dual(c.v) : b);
}

// ---- R-operations (spec §3; fv-method.md §2.4) ----
// Written over operand *getters* so that one formula serves both engines: the voxel engine's
// getters return stored operand values; the classic engine's getters re-evaluate the operand
// sub-tree each time the defining formula references it, as the papers' recursive R-functional
// evaluation does. alpha == 0: R0; alpha == 1: R1 = MINMAX; otherwise R_alpha, alpha in (-1, 1).

template <class T> inline T square(const T& a) { return a * a; }

template <class GetA, class GetB>
inline auto r_conjunction(GetA a, GetB b, double alpha) -> std::remove_cvref_t<decltype(a())> {
    using T = std::remove_cvref_t<decltype(a())>;
    if (alpha == 0.0) return a() + b() - k_sqrt(square(a()) + square(b()));
    if (alpha == 1.0) return k_min(a(), b());
    return (a() + b() - k_sqrt(square(a()) + square(b()) - T(2.0 * alpha) * (a() * b()))) / T(1.0 + alpha);
}

template <class GetA, class GetB>
inline auto r_disjunction(GetA a, GetB b, double alpha) -> std::remove_cvref_t<decltype(a())> {
    using T = std::remove_cvref_t<decltype(a())>;
    if (alpha == 0.0) return a() + b() + k_sqrt(square(a()) + square(b()));
    if (alpha == 1.0) return k_max(a(), b());
    return (a() + b() + k_sqrt(square(a()) + square(b()) - T(2.0 * alpha) * (a() * b()))) / T(1.0 + alpha);
}

/// Arithmetic operations the R-formula itself executes (operand evaluations excluded);
/// the classic cost model counts these per node.
inline int r_formula_ops(double alpha) {
    if (alpha == 0.0) return 6;   // + − sqrt sq sq +
    if (alpha == 1.0) return 1;   // min / max
    return 11;                    // + − sqrt sq sq + − 2α· · / (1+α)
}

/// A getter over an already computed value (voxel engine, constant folder).
template <class T> inline auto value_of(const T& v) {
    return [&v]() -> const T& { return v; };
}

}  // namespace fortu::ir
