// interp/parallel.hpp — runtime/parallel.hpp with the engines' options: thread count,
// cancellation (REPL Ctrl-C) and progress. Both engines use it, so their timings compare
// like with like.
#pragma once

#include "interp/engine.hpp"
#include "runtime/parallel.hpp"

namespace fortu {

/// Threads parallel_for will use for `count` items.
inline int worker_count(std::size_t count, const EvalOptions& options) { return worker_count(count, options.threads); }

/// Calls work(i, worker) for i in [0, count) on `options.threads` threads; work returns how
/// many grid points it finished, reported through options.progress. Stops early on cancel.
template <class Work>
void parallel_for(std::size_t count, const EvalOptions& options, Work&& work) {
    parallel_for(count, options.threads, options.cancel, [&](std::size_t i, int worker) {
        const std::size_t points = work(i, worker);
        if (options.progress) options.progress(points);
    });
}

}  // namespace fortu
