// interp/float_gradient.hpp — a tape's value and exact gradient at a batch of points in
// float32 lanes (forward-mode derivatives, structure of arrays).
//
// Why: the shaded view needs, at every pixel it hits, the model's gradient (the normal, and
// one Newton step along the ray). ir::Dual does it in float64 one point at a time with libm:
// a fifth of a 1024² view of bear.vm. Here each instruction's value runs as the float32 lane
// kernel runs it (SLEEF's vector exp/ln), and its three derivative lanes follow from the
// operands' by the same chain rules as ir::Dual's (interp/ir/kernels.hpp), so a batch costs
// a few float32 evaluations. Operations without a rule here make the caller keep ir::Dual.
#pragma once

#include "interp/tape.hpp"

#include <array>
#include <vector>

namespace fortu {

/// Working memory, reused from batch to batch.
struct FloatGradientScratch {
    std::vector<float> values, derivatives, helper;
    std::vector<float*> value_slots;
};

/// Whether every instruction of `tape` has a float32 derivative rule here.
bool float_gradient_supported(const Tape& tape);

/// Evaluates `tape` (its root) at `count` points: points[axis][i] is point i's coordinate.
/// value[i] and gradient[axis][i] receive the root's value and its derivatives. Lanes whose
/// result is not finite are left as computed (the caller decides). Requires
/// float_gradient_supported(tape).
void float_gradients(const Tape& tape, const std::array<const float*, 3>& points, int count, float* value,
                     const std::array<float*, 3>& gradient, FloatGradientScratch& scratch);

}  // namespace fortu
