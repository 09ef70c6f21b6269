// cli/run_checks.cpp — see run_checks.hpp. Validation only: nothing here writes a file.
#include "cli/run_checks.hpp"

#include "runtime/output.hpp"
#include "runtime/output_error.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_path.hpp"
#include "runtime/resources.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>

#include <unistd.h>

namespace fortu {
namespace {

namespace fs = std::filesystem;

// The M-images of a slice: M1..M_{n+2}.
int mimage_count(const Grid& grid) { return grid.dims == 3 ? 5 : 4; }

void add_target(std::vector<PlannedFile>& out, const std::string& option, const std::string& path, int first,
                int count) {
    const OutputTarget target{path, output_format_for(path), is_file_series(path)};
    if (!target.series) {
        out.push_back({option, path});
        return;
    }
    for (int k = first; k < first + count; ++k) out.push_back({option, target.file(k)});
}

// One spelling per file, so that `out.png` and `./out.png` collide.
std::string identity(const std::string& path) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return ec ? path : canonical.string();
}

}  // namespace

std::size_t available_memory() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::size_t kib = 0;
    std::string unit;
    while (meminfo >> key >> kib >> unit)
        if (key == "MemAvailable:") return kib * 1024;
    return 0;   // unknown: not checked
}

std::vector<PlannedFile> planned_files(const CliOptions& o, const Grid& grid) {
    std::vector<PlannedFile> out;
    if (!o.output.empty()) {
        const bool slices = grid.dims == 3 && is_file_series(o.output);
        add_target(out, "-o", o.output, 0, slices ? grid.slices() : 1);
        if (!slices && is_file_series(o.output)) out.back().path = OutputTarget{o.output, nullptr, true}.file(0);
    }
    if (!o.mimages.empty()) add_target(out, "--mimages", o.mimages, 1, mimage_count(grid));
    if (!o.contour.empty()) add_target(out, "--contour", o.contour, 0, 1);
    return out;
}

void check_outputs(const CliOptions& o, const Grid& grid) {
    if (!o.mimages.empty())
        if (const auto problem = mimages_path_problem(o.mimages)) throw UsageError("--mimages: " + *problem);
    std::map<std::string, const PlannedFile*> seen;
    const std::vector<PlannedFile> files = planned_files(o, grid);
    for (const PlannedFile& file : files) {
        const auto [it, fresh] = seen.emplace(identity(file.path), &file);
        if (!fresh)
            throw UsageError(fmt::format("{} and {} would both write '{}'", it->second->option, file.option, file.path));
    }
    for (const PlannedFile& file : files) {
        const fs::path dir = fs::path(file.path).parent_path();
        const std::string shown = dir.empty() ? std::string(".") : dir.string();
        std::error_code ec;
        const fs::file_status status = fs::status(dir.empty() ? fs::path(".") : dir, ec);
        if (!fs::exists(status)) throw OutputError(file.path, "directory '" + shown + "' does not exist");
        if (!fs::is_directory(status)) throw OutputError(file.path, "'" + shown + "' is not a directory");
        if (::access(shown.c_str(), W_OK | X_OK) != 0)
            throw OutputError(file.path, "cannot create a file in '" + shown + "': permission denied");
        if (fs::is_directory(file.path, ec)) throw OutputError(file.path, "is a directory");
    }
}

std::size_t estimated_run_bytes(const CliOptions& o, const Grid& grid) {
    const double points = static_cast<double>(grid.points());
    const double slice_points = static_cast<double>(grid.cols()) * grid.rows();
    double per_point = 8;   // the field's values (float64)
    double writer = 0;      // the largest writer's buffers, alive one at a time
    auto consider = [&](const std::string& path, bool mimages) {
        if (path.empty()) return;
        const OutputFormat* format = output_format_for(path);
        if (!format) return;
        const int channels = grid.dims == 3 ? 6 : 5;
        double bytes = 0;
        switch (format->kind) {
            case OutputKind::MImages:   // float32 value + n1.. per point; all slices in one file
                bytes = (is_file_series(path) ? slice_points : points) * channels * 4.0 * 2;
                break;
            case OutputKind::Picture:   // 8-bit RGB pixels of a slice (+ M-image pictures), encoded copy
                bytes = slice_points * (mimages ? mimage_count(grid) * 3.0 : 4.0) * 2;
                break;
            case OutputKind::Field:     // npy/csv stream, but float32 npy converts the field
                bytes = points * 4.0;
                break;
            default:                    // contours, meshes, volumes: on the order of the field
                bytes = points * 8.0;
                break;
        }
        writer = std::max(writer, bytes);
    };
    consider(o.output, false);
    consider(o.mimages, true);
    consider(o.contour, false);
    return static_cast<std::size_t>(points * per_point + writer);
}

void check_memory(const CliOptions& o, const Grid& grid, std::size_t available) {
    if (o.force) return;
    if (available == 0) available = available_memory();
    if (available == 0) return;
    const std::size_t needed = estimated_run_bytes(o, grid);
    if (needed <= available) return;
    throw UsageError(fmt::format("the run needs about {} of memory ({} points and its outputs), more than the {} "
                                 "available\nnote: use a smaller --size, fewer outputs, or --force",
                                 format_bytes(needed), format_count(grid.points()), format_bytes(available)));
}

}  // namespace fortu
