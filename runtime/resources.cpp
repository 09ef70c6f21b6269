// runtime/resources.cpp — getrusage and number formatting.
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <cmath>

#include <sys/resource.h>

namespace fortu {

std::size_t peak_rss_bytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0 || usage.ru_maxrss < 0) return 0;
    return static_cast<std::size_t>(usage.ru_maxrss) * 1024;   // Linux reports KiB
}

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
