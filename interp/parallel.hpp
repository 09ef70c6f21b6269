// interp/parallel.hpp — runs independent work items (rows, tiles) on worker threads.
// Both engines use it, so their timings compare like with like.
#pragma once

#include "interp/engine.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace fortu {

inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? static_cast<int>(cores) : 1;
}

/// Threads parallel_for will use for `count` items.
inline int worker_count(std::size_t count, const EvalOptions& options) {
    return static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(resolve_threads(options.threads), count)));
}

/// Calls work(i, worker) for i in [0, count) on `options.threads` threads (worker is the
/// thread's index, for per-thread scratch space); work returns how many grid points it
/// finished, reported through options.progress. Stops early on cancel.
template <class Work>
void parallel_for(std::size_t count, const EvalOptions& options, Work&& work) {
    std::atomic<std::size_t> next{0};
    auto worker = [&](int worker_index) {
        for (;;) {
            if (options.cancel && options.cancel->load(std::memory_order_relaxed)) return;
            const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
            if (i >= count) return;
            const std::size_t points = work(i, worker_index);
            if (options.progress) options.progress(points);
        }
    };
    const int threads = worker_count(count, options);
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
    worker(0);
    for (std::thread& t : pool) t.join();
}

}  // namespace fortu
