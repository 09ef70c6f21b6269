// cli/bench/bench_report.cpp — text, JSON and CSV renderings of bench cells. The JSON is written by
// hand (a few fixed shapes) so its key order and number format stay stable across versions.
#include "cli/bench/bench_report.hpp"

#include "interp/ir_print.hpp"
#include "runtime/resources.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <set>
#include <thread>

namespace fortu {
namespace {

constexpr double kSecondsPerYear = 365.25 * 86400;

/// Displayed characters (UTF-8 continuation bytes take no column).
std::size_t columns(const std::string& s) {
    std::size_t shown = 0;
    for (unsigned char c : s) shown += (c & 0xC0) != 0x80;
    return shown;
}

std::string pad(const std::string& s, std::size_t width) {
    const std::size_t shown = columns(s);
    return shown >= width ? s : s + std::string(width - shown, ' ');
}

std::string right(const std::string& s, std::size_t width) {
    const std::size_t shown = columns(s);
    return shown >= width ? s : std::string(width - shown, ' ') + s;
}

const BenchCell* find_cell(const std::vector<BenchCell>& cells, const std::string& model, const std::string& size,
                           const Engine& engine) {
    for (const BenchCell& c : cells)
        if (c.model == model && grid_text(c.grid) == size && c.engine == &engine) return &c;
    return nullptr;
}

}  // namespace

std::string estimate_text(double seconds) {
    if (!(seconds >= 0)) return "?";
    if (seconds >= kSecondsPerYear) return fmt::format("{:.3g} years", seconds / kSecondsPerYear);
    return format_duration(seconds);
}

MachineInfo describe_machine() {
    MachineInfo m;
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            m.cpu = colon == std::string::npos ? "" : line.substr(line.find_first_not_of(" \t", colon + 1));
            break;
        }
    if (m.cpu.empty()) m.cpu = "unknown CPU";
    m.cores = int(std::max(1u, std::thread::hardware_concurrency()));
#if defined(__clang__)
    m.compiler = fmt::format("clang {}", __clang_version__);
#elif defined(__GNUC__)
    m.compiler = fmt::format("GCC {}", __VERSION__);
#else
    m.compiler = "unknown compiler";
#endif
#ifdef NDEBUG
    m.build = "optimised (NDEBUG)";
#else
    m.build = "debug (assertions on)";
#endif
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    m.date = date;
    return m;
}

std::string machine_text(const MachineInfo& m) {
    return fmt::format("{}, {} core{}, {}, {} build", m.cpu, m.cores, m.cores == 1 ? "" : "s", m.compiler, m.build);
}

std::string run_text(const MachineInfo& m, int threads, double seconds) {
    return fmt::format("Machine: {}. Threads per run: {}. Run at {} in {}", machine_text(m),
                       threads > 0 ? threads : m.cores, m.date, format_duration(seconds));
}

std::string memory_method_text() {
    return memory_method() == std::string("clear_refs") ? "resetting the kernel's peak-RSS mark (clear_refs) before it"
                                                        : "the process's ru_maxrss";
}

std::vector<BenchRatio> bench_ratios(const std::vector<BenchCell>& cells) {
    std::vector<BenchRatio> ratios;
    for (const BenchCell& c : cells) {
        if (!c.engine->capabilities().expanded_tree_cost) continue;
        const std::string size = grid_text(c.grid);
        const BenchCell* v = find_cell(cells, c.model, size, engine_named("voxel"));
        if (!v || v->skipped || v->median <= 0) continue;
        if (c.skipped && c.estimated_seconds < 0) continue;
        ratios.push_back({c.model, c.shown_name(), size, (c.skipped ? c.estimated_seconds : c.median) / v->median, c.skipped});
    }
    return ratios;
}

std::string duration_text(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    // Three significant digits; a value that would round up to 1000 moves on to the next unit.
    auto three_digits = [](double v) {
        if (v < 9.995) return fmt::format("{:.2f}", v);
        if (v < 99.95) return fmt::format("{:.1f}", v);
        return fmt::format("{:.0f}", v);
    };
    if (seconds < 999.5e-9) return three_digits(seconds * 1e9) + " ns";
    if (seconds < 999.5e-6) return three_digits(seconds * 1e6) + " µs";
    return estimate_text(seconds);
}

std::vector<std::string> model_labels(const std::vector<std::string>& paths) {
    std::map<std::string, std::set<std::string>> paths_of_stem;
    std::vector<std::string> stems;
    for (const std::string& path : paths) {
        std::string stem = std::filesystem::path(path).stem().string();
        if (stem.empty()) stem = path;
        paths_of_stem[stem].insert(path);
        stems.push_back(stem);
    }
    for (std::size_t i = 0; i < paths.size(); ++i)
        if (paths_of_stem[stems[i]].size() > 1) stems[i] = paths[i];
    return stems;
}

namespace {

/// The widths of the fixed columns: a duration is at most "17 min 29 s".
constexpr std::size_t kRunsWidth = 4, kTimeWidth = 11, kPerPointWidth = 9, kOpsWidth = 11, kMimagesWidth = 12;

}  // namespace

BenchTableLayout bench_table_layout(const std::vector<BenchCell>& planned, bool mimages) {
    BenchTableLayout l;
    l.mimages = mimages;
    for (const BenchCell& c : planned) {
        l.model = std::max(l.model, columns(c.shown_name()));
        l.engine = std::max(l.engine, c.engine->name().size());
        l.size = std::max(l.size, grid_text(c.grid).size());
        l.points = std::max(l.points, format_count(c.points()).size());
    }
    return l;
}

std::string bench_table_header(const BenchTableLayout& l) {
    std::string out = pad("model", l.model) + "  " + pad("engine", l.engine) + "  " + pad("size", l.size) + "  " +
                      right("points", l.points) + "  " + right("runs", kRunsWidth) + "  " + right("min", kTimeWidth) +
                      "  " + right("median", kTimeWidth) + "  " + right("max", kTimeWidth) + "  " +
                      right("per point", kPerPointWidth) + "  " + right("ops/point", kOpsWidth) + "  ";
    if (l.mimages) out += pad("M-images", kMimagesWidth) + "  ";
    return out + "peak memory (growth)\n";
}

std::string bench_table_row(const BenchTableLayout& l, const BenchCell& c) {
    std::string out = pad(c.shown_name(), l.model) + "  " + pad(std::string(c.engine->name()), l.engine) + "  " +
                      pad(grid_text(c.grid), l.size) + "  " + right(format_count(c.points()), l.points) + "  ";
    if (c.skipped)
        return out + fmt::format("skipped: {}; estimated {} ({} operations per point)\n", c.skip_reason,
                                 duration_text(c.estimated_seconds), format_operations(c.operations_per_point));
    out += right(std::to_string(c.seconds.size()), kRunsWidth) + "  " + right(duration_text(c.min), kTimeWidth) +
           "  " + right(duration_text(c.median), kTimeWidth) + "  " + right(duration_text(c.max), kTimeWidth) + "  " +
           right(duration_text(c.seconds_per_point()), kPerPointWidth) + "  " +
           right(format_operations(c.operations_per_point), kOpsWidth) + "  ";
    if (l.mimages)
        out += pad(c.mimages ? fmt::format("{} in {}", c.mimages, duration_text(c.mimages_median)) : "-",
                   kMimagesWidth) + "  ";
    return out + fmt::format("{} (+{})\n", format_bytes(c.peak_rss_bytes), format_bytes(c.rss_growth_bytes));
}

std::string bench_table(const std::vector<BenchCell>& cells) {
    bool mimages = false;
    for (const BenchCell& c : cells) mimages |= c.mimages > 0;
    const BenchTableLayout layout = bench_table_layout(cells, mimages);
    std::string out = bench_table_header(layout);
    for (const BenchCell& c : cells) out += bench_table_row(layout, c);
    return out;
}

std::string ratio_text(const std::vector<BenchRatio>& ratios) {
    std::string out;
    for (const BenchRatio& r : ratios)
        out += fmt::format("ratio classic/voxel, {} {}: {}{:.3g}{}\n", r.label, r.size, r.estimated ? "≈ " : "",
                           r.classic_over_voxel, r.estimated ? " (estimated: classic skipped)" : "");
    return out;
}

std::string json_number(double v) {
    if (!std::isfinite(v)) return "null";
    return fmt::format("{}", v);
}

std::string json_numbers(const std::vector<double>& values) {
    std::string out;
    for (double v : values) out += (out.empty() ? "" : ", ") + json_number(v);
    return out;
}

std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += char(c);
        else if (c == '\n') out += "\\n";
        else if (c < 0x20) out += fmt::format("\\u{:04x}", c);
        else out += char(c);
    }
    return out + "\"";
}

std::string cell_json(const BenchCell& c, int indent) {
    const std::string in(indent, ' ');
    const std::string seconds = json_numbers(c.seconds), cpu = json_numbers(c.cpu_seconds);
    std::string size = fmt::format("{}, {}", c.grid.cols(), c.grid.rows());
    if (c.grid.dims == 3) size += fmt::format(", {}", c.grid.slices());
    std::string out = fmt::format(
        "{0}{{\n{0}  \"model\": {1},\n{0}  \"engine\": \"{2}\",\n{0}  \"size\": [{3}],\n{0}  \"points\": {4},\n"
        "{0}  \"operations_per_point\": {5},\n{0}  \"status\": \"{6}\",\n",
        in, json_string(c.model), c.engine->name(), size, c.points(), json_number(c.operations_per_point),
        c.skipped ? "skipped" : "measured");
    if (c.skipped) {
        out += fmt::format("{0}  \"skip_reason\": {1},\n{0}  \"estimated_operations\": {2},\n"
                           "{0}  \"estimated_seconds\": {3}\n{0}}}",
                           in, json_string(c.skip_reason), json_number(c.total_operations()),
                           c.estimated_seconds < 0 ? "null" : json_number(c.estimated_seconds));
    } else {
        out += fmt::format("{0}  \"seconds\": [{1}],\n{0}  \"min_seconds\": {2},\n{0}  \"median_seconds\": {3},\n"
                           "{0}  \"max_seconds\": {4},\n{0}  \"seconds_per_point\": {5},\n"
                           "{0}  \"peak_rss_bytes\": {6},\n{0}  \"rss_growth_bytes\": {7},\n"
                           "{0}  \"cpu_seconds\": [{8}],\n{0}  \"median_cpu_seconds\": {9},\n{0}  \"mimages\": {10}",
                           in, seconds, json_number(c.min), json_number(c.median), json_number(c.max),
                           json_number(c.seconds_per_point()), c.peak_rss_bytes, c.rss_growth_bytes, cpu,
                           json_number(c.cpu_median), c.mimages);
        if (c.mimages)
            out += fmt::format(",\n{0}  \"mimages_seconds\": [{1}],\n{0}  \"median_mimages_seconds\": {2}", in,
                               json_numbers(c.mimages_seconds), json_number(c.mimages_median));
        out += fmt::format("\n{}}}", in);
    }
    return out;
}

std::string machine_json(const MachineInfo& m) {
    return fmt::format("{{\"cpu\": {}, \"cores\": {}, \"compiler\": {}, \"build\": {}, \"date\": {}}}",
                       json_string(m.cpu), m.cores, json_string(m.compiler), json_string(m.build), json_string(m.date));
}

std::string bench_json(const std::vector<BenchCell>& cells, const MachineInfo& m, const MeasureOptions& o) {
    std::string out = fmt::format(
        "{{\n  \"schema\": \"fortu-bench/1\",\n  \"machine\": {},\n  \"options\": {{\"repeat\": {}, "
        "\"repeat_cap_seconds\": {}, \"threads\": {}, \"budget_operations\": {}, \"memory_method\": \"{}\", "
        "\"mimages\": {}}},\n  \"cells\": [\n",
        machine_json(m), o.repeat, json_number(o.repeat_cap), o.threads, json_number(o.budget), memory_method(),
        o.mimages ? "true" : "false");
    for (std::size_t i = 0; i < cells.size(); ++i) out += cell_json(cells[i], 4) + (i + 1 < cells.size() ? ",\n" : "\n");
    out += "  ],\n  \"ratios\": [\n";
    const auto ratios = bench_ratios(cells);
    for (std::size_t i = 0; i < ratios.size(); ++i)
        out += fmt::format("    {{\"model\": {}, \"size\": \"{}\", \"classic_over_voxel\": {}, \"estimated\": {}}}{}\n",
                           json_string(ratios[i].model), ratios[i].size, json_number(ratios[i].classic_over_voxel),
                           ratios[i].estimated ? "true" : "false", i + 1 < ratios.size() ? "," : "");
    return out + "  ]\n}\n";
}

std::string bench_csv(const std::vector<BenchCell>& cells) {
    std::string out = "model,engine,cols,rows,slices,points,status,runs,min_s,median_s,max_s,s_per_point,"
                      "ops_per_point,peak_rss_bytes,estimated_s,mimages,mimages_median_s\n";
    auto quoted = [](const std::string& s) {
        if (s.find_first_of(",\"\n") == std::string::npos) return s;
        std::string q = "\"";
        for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    };
    for (const BenchCell& c : cells) {
        out += fmt::format("{},{},{},{},{},{},{},", quoted(c.model), c.engine->name(), c.grid.cols(),
                           c.grid.rows(), c.grid.slices(), c.points(), c.skipped ? "skipped" : "measured");
        if (c.skipped)
            out += fmt::format("0,,,,,{},,{},0,\n", json_number(c.operations_per_point),
                               c.estimated_seconds < 0 ? "" : json_number(c.estimated_seconds));
        else
            out += fmt::format("{},{},{},{},{},{},{},,{},{}\n", c.seconds.size(), json_number(c.min),
                               json_number(c.median), json_number(c.max), json_number(c.seconds_per_point()),
                               json_number(c.operations_per_point), c.peak_rss_bytes, c.mimages,
                               c.mimages ? json_number(c.mimages_median) : "");
    }
    return out;
}

std::optional<LinearFit> fit_line(const std::vector<double>& x, const std::vector<double>& y) {
    const std::size_t n = std::min(x.size(), y.size());
    if (n < 2) return std::nullopt;
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < n; ++i) mx += x[i], my += y[i];
    mx /= double(n);
    my /= double(n);
    double sxx = 0, sxy = 0, syy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sxx += (x[i] - mx) * (x[i] - mx);
        sxy += (x[i] - mx) * (y[i] - my);
        syy += (y[i] - my) * (y[i] - my);
    }
    if (sxx <= 0) return std::nullopt;
    LinearFit f;
    f.slope = sxy / sxx;
    f.intercept = my - f.slope * mx;
    f.r2 = syy > 0 ? (sxy * sxy) / (sxx * syy) : 1.0;
    f.points = int(n);
    return f;
}

PointsFit fit_time_per_point(const std::vector<BenchCell>& cells) {
    PointsFit out;
    std::vector<double> points, seconds;
    for (const BenchCell& c : cells) {
        ++out.cells;
        if (c.skipped) {
            ++out.skipped;
            continue;
        }
        points.push_back(double(c.points()));
        seconds.push_back(c.median);
    }
    out.fit = fit_line(points, seconds);
    return out;
}

std::string points_fit_text(const std::string& engine, const PointsFit& fit) {
    const int measured = fit.cells - fit.skipped;
    const std::string skipped = fmt::format("{} skipped over budget", fit.skipped);
    if (!fit.fit)
        return fmt::format("- {}: no fit: {} of {} sizes measured{}\n", engine, measured, fit.cells,
                           fit.skipped ? ", " + skipped : "");
    std::string line = fmt::format("- {}: time = {:.1f} ns per point (+ {}), straight-line fit R² {:.4f}", engine,
                                   fit.fit->slope * 1e9, format_duration(std::max(0.0, fit.fit->intercept)), fit.fit->r2);
    if (fit.skipped) line += fmt::format("; fit over {} of {} sizes, {}", measured, fit.cells, skipped);
    return line + "\n";
}

}  // namespace fortu
