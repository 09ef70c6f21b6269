// cli/sweep.cpp — parameter sweeps over CONSTANTs (sweep.hpp).
#include "cli/sweep.hpp"

#include "cli/run_checks.hpp"

#include "runtime/brick_output.hpp"
#include "runtime/parallel.hpp"
#include "runtime/progress.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <exception>
#include <iostream>
#include <thread>

namespace fortu {
namespace {

double parse_number(const std::string& text, const std::string& whole) {
    double v = 0;
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v))
        throw UsageError(fmt::format("--set: '{}' is not NAME=VALUE or NAME=FIRST:LAST:STEP", whole));
    return v;
}

/// Most points one sweep runs (a typo such as a step of 1e-9 is refused, not started).
constexpr std::size_t kMaxSweepPoints = 100000;

}  // namespace

SweepAxis parse_sweep(const std::string& text) {
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
        throw UsageError(fmt::format("--set: '{}' is not NAME=VALUE or NAME=FIRST:LAST:STEP", text));
    SweepAxis axis{text.substr(0, eq), {}};
    const std::string range = text.substr(eq + 1);
    std::vector<std::string> parts;
    for (std::size_t at = 0;;) {
        const std::size_t colon = range.find(':', at);
        parts.push_back(range.substr(at, colon == std::string::npos ? std::string::npos : colon - at));
        if (colon == std::string::npos) break;
        at = colon + 1;
    }
    if (parts.size() == 1) {
        axis.values = {parse_number(parts[0], text)};
        return axis;
    }
    if (parts.size() != 3) throw UsageError(fmt::format("--set: '{}' is not NAME=VALUE or NAME=FIRST:LAST:STEP", text));
    const double first = parse_number(parts[0], text), last = parse_number(parts[1], text),
                 step = parse_number(parts[2], text);
    if (step == 0 || (last - first) / step < 0)
        throw UsageError(fmt::format("--set: the step of '{}' does not go from {} to {}", text, first, last));
    // The last value counts when the steps reach it within rounding, relative to their number.
    const double steps = (last - first) / step;
    const double count = std::floor(steps + 1e-9 * std::max(1.0, steps)) + 1;
    if (count > double(kMaxSweepPoints))
        throw UsageError(fmt::format("--set: '{}' has {} values, more than {}", text, count, kMaxSweepPoints));
    // first + k * step, read back from 15 significant digits: 0.1 + 2 * 0.1 is
    // 0.30000000000000004, and the run must be the script with 0.3 written in, as its file
    // name (%R: 0.3) says.
    for (std::size_t k = 0; k < std::size_t(count); ++k) {
        const std::string text = fmt::format("{:.15g}", first + double(k) * step);
        axis.values.push_back(parse_number(text, text));
    }
    return axis;
}

std::string sweep_path(const std::string& path, const std::vector<std::pair<std::string, double>>& point) {
    std::string out = path;
    // Longest names first, so %RR is not taken for %R followed by R.
    std::vector<std::pair<std::string, double>> sorted = point;
    std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first.size() > b.first.size(); });
    for (const auto& [name, value] : sorted) {
        const std::string key = "%" + name, text = fmt::format("{:.15g}", value);
        for (std::size_t at = out.find(key); at != std::string::npos; at = out.find(key, at + text.size()))
            out.replace(at, key.size(), text);
    }
    return out;
}

namespace {

/// The CliOptions of point n of the product of `axes` (the first axis varies fastest).
CliOptions point_options(const CliOptions& o, const std::vector<SweepAxis>& axes, std::uint64_t n) {
    CliOptions point = o;
    point.sets.clear();
    point.sweep_point = true;
    std::uint64_t rest = n;
    for (const SweepAxis& a : axes) {
        point.constants.emplace_back(a.name, a.values[rest % a.values.size()]);
        rest /= a.values.size();
    }
    for (std::string* path : {&point.output, &point.mimages, &point.contour}) *path = sweep_path(*path, point.constants);
    return point;
}

/// A bricked run bounds its memory and already spreads its bricks over every thread: two of
/// them side by side would break --memory.
bool runs_bricked(const CliOptions& o) {
    return o.memory > 0 || o.resume || (!o.output.empty() && brick_output_only(o.output)) ||
           (!o.mimages.empty() && brick_output_only(o.mimages));
}

/// Points 1.. of a sweep on one process, `side_by_side` at a time, each on its share of the
/// threads. Their bars stay off: they would fight over one terminal line, and a sweep's bar
/// would be cut by the runs' `wrote` lines, which show the progress instead.
int run_side_by_side(const CliOptions& o, const std::vector<SweepAxis>& axes, std::size_t points, int side_by_side,
                     const std::function<int(const CliOptions&)>& run_one) {
    const int threads_each = std::max(1, resolve_threads(o.threads) / side_by_side);
    std::atomic<std::uint64_t> next{1};
    std::atomic<int> worst{0};
    std::atomic<bool> failed{false};
    std::exception_ptr failure;
    auto worker = [&] {
        const Progress::Quiet quiet;
        try {
            for (std::uint64_t n = next++; n < points && !failed.load(); n = next++) {
                CliOptions point = point_options(o, axes, n);
                point.threads = threads_each;
                const int status = run_one(point);
                for (int w = worst.load(); status > w && !worst.compare_exchange_weak(w, status);) {}
            }
        } catch (...) {
            if (!failed.exchange(true)) failure = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < side_by_side; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    return worst.load();
}

}  // namespace

int run_sweep(const CliOptions& o, const std::function<int(const CliOptions&)>& run_one, const SweepCounter& shared_next) {
    std::vector<SweepAxis> axes;
    for (const std::string& s : o.sets) axes.push_back(parse_sweep(s));
    std::size_t points = 1;
    for (const SweepAxis& a : axes) {
        points *= a.values.size();
        if (points > kMaxSweepPoints) throw UsageError(fmt::format("--set: more than {} runs", kMaxSweepPoints));
        if (a.values.size() > 1)
            for (const std::string* path : {&o.output, &o.mimages, &o.contour})
                if (!path->empty() && path->find("%" + a.name) == std::string::npos)
                    throw UsageError(fmt::format("--set {}: '{}' has no %{}, so every run would overwrite it", a.name,
                                                 *path, a.name));
    }
    auto one_after_another = [&](const SweepCounter& next) {
        int worst = 0;
        for (std::uint64_t n = next(); n < points; n = next()) worst = std::max(worst, run_one(point_options(o, axes, n)));
        return worst;
    };
    if (shared_next) return one_after_another(shared_next);

    // One process: the first run alone on every thread, its footprint measured. A first run
    // that failed ends the sweep: what fails it (a script error, a --set name the script
    // lacks, a missing folder) would fail every run alike.
    const PeakMemoryProbe memory;
    const int first = run_one(point_options(o, axes, 0));
    if (first != 0 && points > 1) {
        std::cerr << fmt::format("fortu: note: the sweep stops: its first run failed ({} more not started)\n",
                                 points - 1);
        return first;
    }
    // Then the rest side by side, as many as there are threads and as half the free memory
    // holds: a run's serial parts (compiling, drawing and encoding a picture) overlap instead of
    // leaving cores idle. Bricked runs bound their memory and use every thread already.
    std::size_t side_by_side = runs_bricked(o) ? 1 : std::min<std::size_t>(resolve_threads(o.threads), points - 1);
    if (const std::size_t available = available_memory(); available > 0 && side_by_side > 1)
        side_by_side = std::clamp<std::size_t>(available / 2 / std::max<std::size_t>(memory.growth(), 1), 1,
                                               side_by_side);
    if (side_by_side <= 1) {
        std::uint64_t n = 1;
        return std::max(first, one_after_another([&n] { return n++; }));
    }
    return run_side_by_side(o, axes, points, int(side_by_side), run_one);
}

}  // namespace fortu
