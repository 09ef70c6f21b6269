// runtime/spread_thread.hpp — a worker thread that starts on another core than the thread
// creating it, then may run on any core the process may.
//
// Why: Linux puts a new thread on its creator's core, and an idle core takes it over only
// at its next load-balancing pass. While the creator works on (as parallel_for's caller
// does, taking items itself), the new thread waited for it: measured here (2-core VM), a
// thread made beside a 2 ms busy loop started after 46-87 µs in 17 of 40 runs and after
// 0.4-2.0 ms in the others, so a two-thread tanglecube.vm sign volume was often rendered by
// one thread. Started with an affinity that leaves the creator's core out, it ran elsewhere
// at once (37-215 µs, every run); it then widens its affinity back to the process's, so the
// scheduler stays free to move it (docs/performance.md, "Threads that start at once").
#pragma once

#include <pthread.h>

#include <functional>

namespace fortu {

class SpreadThread {
public:
    /// Starts `work` on a new thread (std::system_error if the system has none to give).
    explicit SpreadThread(std::function<void()> work);
    SpreadThread(SpreadThread&& other) noexcept : thread_(other.thread_), joinable_(other.joinable_) {
        other.joinable_ = false;
    }
    SpreadThread& operator=(SpreadThread&&) = delete;
    SpreadThread(const SpreadThread&) = delete;
    ~SpreadThread() { join(); }

    /// Waits for `work` to return; does nothing the second time.
    void join();

private:
    pthread_t thread_{};
    bool joinable_ = false;
};

}  // namespace fortu
