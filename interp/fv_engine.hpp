// interp/fv_engine.hpp — the papers' functional-voxel method itself: every intermediate
// result is stored as its M-images, and every operation is FV arithmetic on its operands'
// M-images (fv-method.md §2.2).
//
// Why: the voxel engine keeps exact node values and makes M-images once, at the end; the
// papers' method keeps M-images only, quantised to a palette, and rebuilds each operand's
// local function to compute the next node. Its cost per operation and its accuracy (palette
// quantisation, planes refitted at every step) are what a researcher of the method measures;
// no exact evaluator shows them.
//
// Per IR node, for every grid node q: each operand's value at q is its local function, read
// from its M-images at q, evaluated at q's world coordinates (§2.2's loop, "v_F[k]"); the
// operation is the node's kernel (ops.def, the same as every engine's); the result's plane
// through q and its stencil neighbours (FvStencil, §1.1/§1.2) is normalised and encoded in
// the palette. §2.2 computes the three stencil values per pixel; an operand's value at q
// depends on q alone, so computing it once per node gives the same M-images at a third of
// the operations. Numbers (constants) enter as exact immediates ("multiplication by a
// number", S1), coordinates X, Y, Z as the M-images of their planes.
//
// SQRT's operand is taken as 0 where the recovered value is within the precision of its
// M-images of 0, or below 0 by a small multiple of it (§2.2: "OP must handle √ of a
// negative argument (clamp at 0)"): a FLOZ is
// exactly 0 on its segment, and the recovered value there is ±(rounding or palette step),
// whose root would be 1e-8 (unquantised) or NaN instead of 0. Clearly negative operands stay
// invalid points, as in the exact engines.
//
// The order and the memory come from the voxel engine's tape (tape.hpp): its instructions in
// order, its slots as M-image stores, so a store is reused once its value's last use has
// passed and memory holds only the M-images later nodes still need.
#pragma once

#include "interp/engine.hpp"

namespace fortu {

struct FvOptions {
    /// P = 256 grey (the papers' default), P = 2^24 RGB, or unquantised doubles.
    MimageStorage storage = MimageStorage::Grey8;
};

class FvEngine final : public Engine {
public:
    explicit FvEngine(FvOptions options = {}) : options_(options) {}
    std::string_view name() const override { return "fv"; }
    std::string_view summary() const override;
    std::string description() const override;
    EngineCapabilities capabilities() const override;
    std::unique_ptr<Engine> tuned(const EngineSettings& settings) const override;
    Field evaluate_grid(const ir::Graph& graph, ir::NodeId root, const Grid& grid, const EvalOptions& options,
                        const NodeValues& reuse) const override;

private:
    FvOptions options_;
};

/// `P = 256`, `P = 2^24` or `unquantised`.
std::string storage_text(MimageStorage storage);

}  // namespace fortu
