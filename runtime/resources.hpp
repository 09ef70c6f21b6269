// runtime/resources.hpp — what a run cost: wall time, peak memory, and the number formatting
// used to report them (`--stats`, `fortu bench`).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>

namespace fortu {

/// The peak resident set size of this process so far (getrusage ru_maxrss), in bytes; 0 if
/// the system cannot tell.
std::size_t peak_rss_bytes();

/// The peak resident memory of a stretch of work: from construction on when the kernel lets
/// the peak mark be reset (/proc/self/clear_refs), else the process's peak so far. Resetting
/// the mark also lowers what peak_rss_bytes() reports afterwards.
class PeakMemoryProbe {
public:
    PeakMemoryProbe();
    std::size_t peak() const;     ///< bytes
    std::size_t growth() const;   ///< peak minus the resident size at construction

private:
    bool per_stretch_ = false;
    std::size_t before_ = 0;
};

/// How PeakMemoryProbe measures, for the reports ("clear_refs" or "ru_maxrss").
const char* memory_method();

/// Wall-clock time since construction or the last restart(), on the steady clock.
class Stopwatch {
public:
    Stopwatch() : start_(std::chrono::steady_clock::now()) {}
    void restart() { start_ = std::chrono::steady_clock::now(); }
    /// Seconds elapsed, as a double.
    double seconds() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    std::chrono::steady_clock::time_point start_;
};

/// A count with thousands separators: 397393719 → "397,393,719".
std::string format_count(std::uint64_t count);

/// A size in binary units: "512 B", "1.5 KiB", "379.0 MiB", "2.3 GiB" (one decimal from KiB on).
std::string format_bytes(std::size_t bytes);

/// A duration the way the papers quote them: "850 µs", "12.3 ms", "2.35 s", "1 min 51 s",
/// "17 min 29 s", "2 h 05 min". Negative or non-finite input gives "?".
std::string format_duration(double seconds);

}  // namespace fortu
