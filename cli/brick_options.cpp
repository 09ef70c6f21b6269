// cli/brick_options.cpp — rows and parsing of the bricked run's options (brick_options.hpp).
#include "cli/brick_options.hpp"

#include <charconv>
#include <fmt/format.h>

namespace fortu {

std::size_t parse_memory_size(const std::string& text, const std::string& what) {
    double number = 0;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, number);
    double unit = 1;
    if (ec == std::errc() && ptr + 1 == end) {
        switch (*ptr) {
            case 'K': case 'k': unit = 1024.0; break;
            case 'M': case 'm': unit = 1024.0 * 1024; break;
            case 'G': case 'g': unit = 1024.0 * 1024 * 1024; break;
            case 'T': case 't': unit = 1024.0 * 1024 * 1024 * 1024; break;
            default: unit = 0;
        }
        ++ptr;
    }
    if (ec != std::errc() || ptr != end || unit == 0 || !(number * unit >= 1) || number * unit > 1e18)
        throw UsageError(fmt::format("{}: '{}' is not a memory size (use e.g. 2G, 512M or a byte count)", what, text));
    return static_cast<std::size_t>(number * unit);
}

void add_brick_options(OptionTable& t, CliOptions& o) {
    t.option("--memory", "SIZE", "a 3D run to .vti/.vdb in bricks (.pvti/.hdf: always),\n"
                                 "within SIZE (2G, 512M): any --size, refused when\n"
                                 "the bricks in flight cannot fit",
             [&o](const std::string& v) { o.memory = parse_memory_size(v, "--memory"); });
    t.flag("--resume", "a bricked run computes only the bricks its done map\n(FILE.done) lacks, after a kill",
           [&o] { o.resume = true; });
    t.option("--set", "NAME=V|NAME=A:B:STEP", "a sweep: one run per value of CONSTANT NAME (B included),\n"
                                              "files named by %NAME in -o (out_%R.png); repeat for a\n"
                                              "product; spread over the ranks under mpirun, else run\n"
                                              "side by side on the threads after the first",
             [&o](const std::string& v) { o.sets.push_back(v); });
    t.option("--brick-times", "FILE.csv", "a bricked run appends brick,rank,seconds,evaluated,skipped\n"
                                          "per brick to FILE.csv (load-balance studies)",
             [&o](const std::string& v) { o.brick_times = v; });
    t.option("--brick", "N", "nodes per brick edge of a bricked run (default 128)", [&o](const std::string& v) {
        int n = 0;
        auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
        if (ec != std::errc() || ptr != v.data() + v.size() || n < 8 || n > 1024)
            throw UsageError(fmt::format("--brick: '{}' is not a brick edge from 8 to 1024", v));
        o.brick = n;
    });
}

}  // namespace fortu
