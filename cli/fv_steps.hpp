// cli/fv_steps.hpp — `fortu run --steps DIR`: each named definition's value picture and
// M-images written as the engine computes it, so the papers' step-by-step figures can be
// reproduced (fv-method.md §2.5, S1 Figs. 1–2).
#pragma once

#include "interp/engine.hpp"
#include "runtime/output_options.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace fortu {

/// Writes, for step number I of N (zero-padded to the width of N, at least 2 digits), into
/// DIR: `I_NAME.png`, the value picture; with a palette, `I_NAME_m1.png` .. `_m4.png` (3D:
/// `_m5`, the picture slice), the stored codes themselves (grey, or 24-bit RGB); unquantised,
/// `I_NAME_m.exr` (value and n1.. channels). Names sort in the order of computation.
class StepWriter {
public:
    /// Creates DIR if needed; throws OutputError if it cannot.
    StepWriter(std::string dir, std::size_t steps, OutputOptions options);
    /// Throws OutputError.
    void operator()(const EvalStep& step);
    /// Every file written so far, in order.
    const std::vector<std::string>& files() const { return files_; }

private:
    std::string dir_;
    int width_;
    OutputOptions options_;
    std::vector<std::string> files_;
};

}  // namespace fortu
