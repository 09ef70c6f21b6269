// cli/bench/bench_report.hpp — `fortu bench`'s reports: the terminal table, the JSON document
// (schema "fortu-bench/1", bench/README.md), the CSV rows, the machine description and the
// least-squares fits the paper experiments print.
#pragma once

#include "cli/bench/bench_measure.hpp"

#include <optional>
#include <string>
#include <vector>

namespace fortu {

/// Where the numbers were measured: CPU model (/proc/cpuinfo), cores, compiler, build.
struct MachineInfo {
    std::string cpu;
    int cores = 0;
    std::string compiler;
    std::string build;
    std::string date;   ///< UTC, ISO 8601
};
MachineInfo describe_machine();
std::string machine_text(const MachineInfo& machine);
/// The line every report opens with: "Machine: .... Threads per run: N. Run at DATE in TIME"
/// (no final full stop); `threads` as given on the command line (0: all cores).
std::string run_text(const MachineInfo& machine, int threads, double seconds);
/// How each cell's peak memory was measured, in words for the reports.
std::string memory_method_text();

/// A duration as the papers quote it (format_duration), or "1.2e+25 years" beyond a year —
/// the estimates of skipped classic cells reach far past what format_duration spells out.
std::string estimate_text(double seconds);

/// The median time of classic over voxel for one model and grid; estimated when the classic
/// cell was skipped (its estimate over voxel's median).
struct BenchRatio {
    std::string model;
    std::string label;   ///< the model's short name (BenchCell::shown_name)
    std::string size;
    double classic_over_voxel = 0;
    bool estimated = false;
};
std::vector<BenchRatio> bench_ratios(const std::vector<BenchCell>& cells);

/// A duration with three significant digits in the unit that suits it: "41.9 ns", "2.08 µs",
/// "12.3 ms", "2.35 s", then format_duration's "1 min 51 s".
std::string duration_text(double seconds);

/// Short names for model paths: each file's stem ("s1_fig3a_floz"), or the whole path where
/// two models share a stem, so that no two lines of a table or plot look alike.
std::vector<std::string> model_labels(const std::vector<std::string>& paths);

/// The column widths of a bench table, fixed from the cells planned (not yet measured) so the
/// header and each row can be printed the moment they are known. Every column is followed by
/// two spaces, so no value can run into the next even past its width.
struct BenchTableLayout {
    std::size_t model = 5, engine = 6, size = 4, points = 6;
    bool mimages = false;   ///< an M-images column (--mimages)
};
BenchTableLayout bench_table_layout(const std::vector<BenchCell>& planned, bool mimages);
std::string bench_table_header(const BenchTableLayout& layout);
/// One cell's line (with its newline); skipped cells say why and their estimate after `points`.
std::string bench_table_row(const BenchTableLayout& layout, const BenchCell& cell);
/// Header and rows.
std::string bench_table(const std::vector<BenchCell>& cells);
/// One line per ratio: `ratio classic/voxel, MODEL SIZE: 9.4` (`≈` and "estimated" when estimated).
std::string ratio_text(const std::vector<BenchRatio>& ratios);

/// One cell as a JSON object (bench/README.md).
std::string cell_json(const BenchCell& cell, int indent);
/// A JSON number; null for non-finite values.
std::string json_number(double v);
std::string json_string(const std::string& s);
/// Comma-separated JSON numbers (without the brackets).
std::string json_numbers(const std::vector<double>& values);
/// The "machine" object every bench document carries.
std::string machine_json(const MachineInfo& machine);
/// The whole `fortu bench MODEL...` document.
std::string bench_json(const std::vector<BenchCell>& cells, const MachineInfo& machine, const MeasureOptions& options);
/// Header line plus one row per cell.
std::string bench_csv(const std::vector<BenchCell>& cells);

/// y = intercept + slope·x by least squares, with the coefficient of determination.
struct LinearFit {
    double intercept = 0;
    double slope = 0;
    double r2 = 0;
    int points = 0;
};
/// nullopt with fewer than two points or all x equal.
std::optional<LinearFit> fit_line(const std::vector<double>& x, const std::vector<double>& y);

/// Median time against grid points over the cells that were measured. A skipped (over-budget)
/// cell has no time: counted as 0 s it once bent E4's classic line to a negative time per
/// point, so it leaves the fit and is only counted.
struct PointsFit {
    std::optional<LinearFit> fit;   ///< over the measured cells; nullopt with fewer than two
    int cells = 0;                  ///< cells offered (one per grid size)
    int skipped = 0;                ///< of them, skipped and left out
};
PointsFit fit_time_per_point(const std::vector<BenchCell>& cells);
/// E4's line for one engine: "- classic: time = 41.9 ns per point (+ 2 ms), straight-line fit
/// R² 0.9990", then "; fit over 3 of 4 sizes, 1 skipped over budget" when cells were skipped,
/// or "- classic: no fit: 1 of 4 sizes measured, 3 skipped over budget".
std::string points_fit_text(const std::string& engine, const PointsFit& fit);

}  // namespace fortu
