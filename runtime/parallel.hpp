// runtime/parallel.hpp — independent work items (rows, tiles) shared among worker threads.
// One loop for every layer: the engines (through interp/parallel.hpp), the FV model, the
// image writers. Items are handed out one at a time, so uneven items still balance.
#pragma once

#include "runtime/spread_thread.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace fortu {

/// `requested` threads, or all cores for 0.
inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? static_cast<int>(cores) : 1;
}

/// Threads parallel_for uses for `count` items.
inline int worker_count(std::size_t count, int threads) {
    return static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(resolve_threads(threads), count)));
}

/// Calls work(i, worker) for i in [0, count) on `threads` threads (0: all cores; worker is
/// the thread's index, for per-thread scratch space). Stops handing out items once `cancel`
/// is set. An exception in any item is rethrown here after all threads stopped.
template <class Work>
void parallel_for(std::size_t count, int threads, const std::atomic<bool>* cancel, Work&& work) {
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr failure;
    auto worker = [&](int worker_index) {
        try {
            for (;;) {
                if (failed.load(std::memory_order_relaxed)) return;
                if (cancel && cancel->load(std::memory_order_relaxed)) return;
                const std::size_t i = next.fetch_add(1, std::memory_order_relaxed);
                if (i >= count) return;
                work(i, worker_index);
            }
        } catch (...) {
            if (!failed.exchange(true)) failure = std::current_exception();
        }
    };
    const int workers = worker_count(count, threads);
    std::vector<SpreadThread> pool;   // joined on any exit, so no worker outlives this frame
    pool.reserve(workers);
    for (int t = 1; t < workers; ++t) pool.emplace_back([&worker, t] { worker(t); });
    worker(0);
    for (SpreadThread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace fortu
