// cli/brick_run.hpp — `fortu run` of a 3D model to .vti/.vdb in bricks: out of core within
// --memory, resumable (--resume), and spread over the ranks of `mpirun -np R fortu run ...`.
//
// Why a path of its own: the in-memory run holds the whole field (2^28 points at most); a
// bricked run holds only the bricks in flight (runtime/bricks.hpp), evaluates each with
// interval pruning and exact values (interp/brick_eval.hpp), writes it durably where the
// format keeps it (runtime/brick_output.hpp) and records it in the done map. Bricks are
// drawn from one counter shared by every thread of every rank, so costly bricks (the
// surface's) spread themselves.
#pragma once

#include "cli/cli_options.hpp"
#include "interp/model.hpp"

namespace fortu {

/// True when this run goes in bricks: a 3D model without --slice written to .vti or .vdb,
/// with --memory or --resume, or launched by mpirun with more than one rank.
bool wants_bricks(const Model& model, const CliOptions& o);

/// The bricked run; returns the exit status. Throws UsageError (before any work) for what
/// a bricked run cannot do, or when the bricks in flight cannot fit in --memory.
int run_bricked(const Model& model, const CliOptions& o, double compile_seconds);

}  // namespace fortu
