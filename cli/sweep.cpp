// cli/sweep.cpp — parameter sweeps over CONSTANTs (sweep.hpp).
#include "cli/sweep.hpp"

#include "cli/mpi_world.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <iostream>

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
    const double count = std::floor((last - first) / step + 1e-9) + 1;
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

int run_sweep(const CliOptions& o, const std::function<int(const CliOptions&)>& run_one) {
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
    World& world = World::get();
    World::Counter counter(world);   // the points are shared out like bricks (one at a time)
    int worst = 0;
    for (std::uint64_t n = counter.next(); n < points; n = counter.next()) {
        CliOptions point = o;
        point.sets.clear();
        point.sweep_point = true;
        std::size_t rest = n;
        for (const SweepAxis& a : axes) {
            point.constants.emplace_back(a.name, a.values[rest % a.values.size()]);
            rest /= a.values.size();
        }
        for (std::string* path : {&point.output, &point.mimages, &point.contour}) *path = sweep_path(*path, point.constants);
        worst = std::max(worst, run_one(point));
    }
    return worst;
}

}  // namespace fortu
