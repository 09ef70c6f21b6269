// runtime/progress.hpp — a progress bar on stderr for runs longer than a second
// (architecture.md "Outputs a user expects"); silent when stderr is not a terminal, so logs
// and pipes stay clean.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace fortu {

/// Counts work done from any number of threads and, if drawing is on, redraws one line about
/// ten times a second from a background thread, starting once `delay` seconds have passed.
/// advance() is one relaxed atomic add, cheap enough to call per tile or per row.
class Progress {
public:
    /// Draws on stderr if it is a terminal (isatty), after 1 s, unless a Quiet is alive on
    /// this thread.
    Progress(std::string label, std::size_t total);
    /// Draws on `out` whatever it is, after `delay_seconds`; never if `out` is null (for tests
    /// and embedding).
    Progress(std::string label, std::size_t total, std::FILE* out, double delay_seconds);
    ~Progress() { finish(); }
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Records `n` more units of work done. Thread-safe.
    void advance(std::size_t n = 1) { done_.fetch_add(n, std::memory_order_relaxed); }
    /// While one lives, bars made on its thread by the stderr constructor do not draw: runs
    /// that go side by side (a sweep) would fight over one terminal line.
    class Quiet {
    public:
        Quiet();
        ~Quiet();
        Quiet(const Quiet&) = delete;
        Quiet& operator=(const Quiet&) = delete;

    private:
        bool was_;
    };

    /// Units done so far.
    std::size_t done() const { return done_.load(std::memory_order_relaxed); }
    std::size_t total() const { return total_; }
    /// Stops drawing and clears the line if anything was drawn. Idempotent; call it from the
    /// thread that created the bar, before printing anything else to the same stream.
    void finish();

private:
    void start(bool draw);
    void run();
    void draw();

    std::string label_;
    std::size_t total_;
    std::FILE* out_ = nullptr;
    std::chrono::duration<double> delay_;
    std::chrono::steady_clock::time_point started_;
    std::atomic<std::size_t> done_{0};

    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;      ///< guarded by mutex_
    bool drawn_ = false;     ///< touched only by the drawing thread until it is joined
    std::thread drawer_;
};

}  // namespace fortu
