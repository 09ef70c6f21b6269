// runtime/resources.cpp — getrusage, the peak-RSS mark, and number formatting.
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <malloc.h>
#include <string>

#include <sys/resource.h>

namespace fortu {

std::size_t peak_rss_bytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss < 0) return 0;
    return static_cast<std::size_t>(usage.ru_maxrss) * 1024;   // Linux reports KiB
}

namespace {

/// A field of /proc/self/status in bytes (VmRSS, VmHWM); 0 when unavailable.
std::size_t proc_status_bytes(const std::string& field) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(field + ":", 0) == 0) return std::stoull(line.substr(field.size() + 1)) * 1024;
    return 0;
}

/// Resets the peak-RSS mark; false when the kernel refuses. First hands the memory that
/// earlier work freed back to the kernel: glibc keeps freed blocks (and raises its mmap
/// threshold after a large free), which would otherwise count in the next stretch's RSS.
bool reset_peak_rss() {
#ifdef __GLIBC__
    malloc_trim(0);
#endif
    std::ofstream out("/proc/self/clear_refs");
    out << "5";
    out.flush();
    return bool(out);
}

bool& clear_refs_works() {
    static bool works = reset_peak_rss();
    return works;
}

}  // namespace

PeakMemoryProbe::PeakMemoryProbe()
    : per_stretch_(clear_refs_works() && reset_peak_rss()),
      before_(per_stretch_ ? proc_status_bytes("VmRSS") : peak_rss_bytes()) {}

std::size_t PeakMemoryProbe::peak() const { return per_stretch_ ? proc_status_bytes("VmHWM") : peak_rss_bytes(); }

std::size_t PeakMemoryProbe::growth() const {
    const std::size_t p = peak();
    return p > before_ ? p - before_ : 0;
}

const char* memory_method() { return clear_refs_works() ? "clear_refs" : "ru_maxrss"; }

std::string format_count(std::uint64_t count) {
    const std::string digits = std::to_string(count);
    std::string out;
    out.reserve(digits.size() + digits.size() / 3);
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

std::string format_bytes(std::size_t bytes) {
    static constexpr const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    if (bytes < 1024) return fmt::format("{} B", bytes);
    double value = static_cast<double>(bytes) / 1024.0;
    std::size_t unit = 0;
    while (value >= 1023.95 && unit + 1 < std::size(kUnits)) {
        value /= 1024.0;
        ++unit;
    }
    return fmt::format("{:.1f} {}", value, kUnits[unit]);
}

std::string format_duration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0.0) return "?";
    // Three significant digits without ever printing "1e+03": a value that would round up
    // to 1000 (or to 60 s) moves on to the next unit.
    auto three_digits = [](double v) {
        if (v < 9.995) return fmt::format("{:.2f}", v);
        if (v < 99.95) return fmt::format("{:.1f}", v);
        return fmt::format("{:.0f}", v);
    };
    if (seconds < 999.5e-6) return fmt::format("{:.0f} µs", seconds * 1e6);
    if (seconds < 0.9995) return three_digits(seconds * 1e3) + " ms";
    if (seconds < 59.5) return three_digits(seconds) + " s";
    const auto whole = static_cast<std::uint64_t>(std::llround(seconds));
    if (whole < 3600) return fmt::format("{} min {} s", whole / 60, whole % 60);
    const auto minutes = static_cast<std::uint64_t>(std::llround(seconds / 60.0));
    return fmt::format("{} h {:02d} min", minutes / 60, minutes % 60);
}

}  // namespace fortu
