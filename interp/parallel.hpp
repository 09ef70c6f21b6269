// interp/parallel.hpp — runtime/parallel.hpp with the engines' options: thread count,
// cancellation (REPL Ctrl-C) and progress. Both engines use it, so their timings compare
// like with like.
#pragma once

#include "interp/engine.hpp"
#include "runtime/parallel.hpp"

#include <algorithm>

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

/// Calls work(begin, end, worker) for the consecutive ranges of at most `chunk` items that
/// make up [0, count), a range per parallel_for item: for items too small to hand out alone.
template <class Work>
void parallel_ranges(std::size_t count, std::size_t chunk, const EvalOptions& options, Work&& work) {
    parallel_for((count + chunk - 1) / chunk, options, [&](std::size_t c, int worker) {
        work(c * chunk, std::min(count, (c + 1) * chunk), worker);
        return std::size_t{0};
    });
}

}  // namespace fortu
