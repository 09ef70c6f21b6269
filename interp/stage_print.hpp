// interp/stage_print.hpp — `fortu ir --stage lower|tape|hoist`: the model after each stage
// of the voxel pipeline, as text (Halide's "print the IR after each pass").
//
// Why: the lowered DAG (ir_print.hpp) says what is computed; the tape says how the voxel
// engine runs it (which slot each value lives in, which operands are immediates); the
// hoisted split says what runs once per grid column, once per row and at every point.
// Looking at each stage is how a slow model or a pass's mistake is found.
#pragma once

#include "interp/model.hpp"
#include "interp/tape.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fortu {

enum class IrStage { Lower, Tape, Hoist };

/// "lower", "tape" or "hoist"; nullopt for anything else.
std::optional<IrStage> parse_ir_stage(std::string_view name);

/// How print_tape names what comes from outside the tape and what leaves it.
struct TapeNaming {
    std::string input = "in";        ///< input k prints as `in k`
    std::string uniform = "uniform"; ///< an operand reading uniform k prints as `uniform[k]`
    std::string output;              ///< output k prints as `OUTPUT k = sN`; empty: `return sN` (one output)
};

/// One line per slot filled from outside (arguments, inputs, constants), one per
/// instruction (`s5 = mul s3 2`: slot operands as sN, immediates as numbers), then the outputs.
std::string print_tape(const Tape& tape, const std::vector<std::string>& arguments, const TapeNaming& naming = {});

/// The model after `stage`: Lower — the DAG (print_ir); Tape — the tape the voxel engine
/// runs without hoisting; Hoist — the column, row and per-point tapes of a grid wide enough
/// to hoist.
std::string print_stage(const Model& model, const std::string& title, IrStage stage);

}  // namespace fortu
