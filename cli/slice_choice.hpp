// cli/slice_choice.hpp — what `--slice` names: a plane of a 3D model, by coordinate
// (`z=0.3`, `x=-1.2`, `y=0`) or by the index of a z slice of the grid (`12`).
#pragma once

#include <optional>
#include <string>

namespace fortu {

struct SliceChoice {
    int axis = 2;                ///< 0 x, 1 y, 2 z
    std::optional<int> index;    ///< a z slice of the --size grid
    double at = 0.0;             ///< the coordinate, when no index
};

/// Parses `K`, `x=V`, `y=V` or `z=V`; throws UsageError naming --slice when malformed.
SliceChoice parse_slice_choice(const std::string& text);

}  // namespace fortu
