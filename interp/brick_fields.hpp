// interp/brick_fields.hpp — one brick's values and, for --mimages, the FV model's components
// of its nodes: what a bricked run hands to its writers.
//
// Why an overlap: a node's components are the hyperplane through it and its forward
// neighbours (fv_model.hpp), so a brick's last column, top row and last slice read nodes of
// the next bricks. The brick is evaluated over its stencils' reach (one node more on each
// forward side where the grid has one, FvStencil::reach), those values are exact wherever
// they are computed (brick_eval.hpp), and the components come from the whole grid's
// coordinates: each brick's components equal the in-memory run's bit for bit. The overlap's
// values are computed twice, once per brick that reads them; that costs (e+1)²/e² - 1 more
// evaluation on bricks of e rows and slices (2% at 90 rows × 91 slices), less than keeping
// the neighbours' faces in flight.
#pragma once

#include "interp/brick_eval.hpp"
#include "runtime/fv_model.hpp"

#include <optional>
#include <vector>

namespace fortu {

/// A brick's arrays, reused from brick to brick by one worker.
struct BrickFields {
    std::vector<double> values;       ///< the brick's own nodes, BrickBox::local order
    std::vector<double> components;   ///< with components: n_k of node i at [(k-1) * points + i]; else empty
    std::vector<double> reach;        ///< scratch: the values over the stencils' reach
};

/// Evaluates bricks with or without their components; one instance per thread.
class BrickFieldEvaluator {
public:
    BrickFieldEvaluator(const ir::Graph& graph, ir::NodeId root, const Grid& grid, bool components);

    /// The brick's values (and components) into `out`. skip_beyond: as BrickEvaluator's,
    /// for value-only writers (components need every value of the reach).
    BrickStats evaluate(const BrickBox& box, BrickFields& out, std::optional<double> skip_beyond = std::nullopt);

private:
    BrickEvaluator values_;
    std::optional<FvStencil> stencil_;
};

/// Bytes of the BrickFields of the largest brick of `layout` (the values; with components
/// also the reach's values and n1.., 5 arrays in 3D).
std::size_t brick_fields_bytes(const BrickLayout& layout, bool components);

}  // namespace fortu
