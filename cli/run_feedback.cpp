// cli/run_feedback.cpp — see run_feedback.hpp.
#include "cli/run_feedback.hpp"

#include "cli/run_checks.hpp"
#include "cli/standard_streams.hpp"
#include "runtime/output_formats.hpp"
#include "runtime/output_path.hpp"

#include <filesystem>
#include <fmt/format.h>

namespace fortu {
namespace {

/// The picture of one plane of `grid`, as plane_picture() turns it: an x or y plane shows Z up.
std::string plane_size(const Grid& grid) {
    const bool spans_z = grid.dims == 3 && grid.slices() > 1;
    if (spans_z && grid.cols() == 1) return fmt::format("{}x{}", grid.rows(), grid.slices());
    if (spans_z && grid.rows() == 1) return fmt::format("{}x{}", grid.cols(), grid.slices());
    return fmt::format("{}x{}", grid.cols(), grid.rows());
}

std::string grid_size(const Grid& grid) {
    return grid.dims == 3 ? fmt::format("{}x{}x{}", grid.cols(), grid.rows(), grid.slices())
                          : fmt::format("{}x{}", grid.cols(), grid.rows());
}

}  // namespace

std::string written_lines(const CliOptions& o, const Grid& grid) {
    if (o.quiet) return {};
    std::string lines;
    for (const PlannedFile& file : planned_files(o, grid)) {
        const std::string& target = file.option == "-o" ? o.output : file.option == "--mimages" ? o.mimages : o.contour;
        const OutputFormat* format = output_format_for(file.path);
        const bool one_plane = is_file_series(target) || grid.dims == 2 || grid.slices() == 1 ||
                               grid.cols() == 1 || grid.rows() == 1;
        const bool picture = format && (format->kind == OutputKind::Picture || format->kind == OutputKind::Contour);
        const bool flat = picture || (one_plane && file.option == "--mimages");
        const std::string size = flat ? plane_size(grid) : grid_size(grid);
        lines += fmt::format("wrote {} ({})\n", shown_output_path(file.path), size);
    }
    return lines;
}

std::string written_steps_line(const CliOptions& o, const Grid& grid, const std::vector<std::string>& files) {
    if (o.quiet || files.empty()) return {};
    const auto name = [](const std::string& path) { return std::filesystem::path(path).filename().string(); };
    return fmt::format("wrote {} step file{} ({}) into {}: {}{}\n", files.size(), files.size() == 1 ? "" : "s",
                       plane_size(grid), shown_output_path(o.steps), name(files.front()),
                       files.size() == 1 ? "" : " ... " + name(files.back()));
}

std::string written_picture_line(const CliOptions& o, const std::string& path, int width, int height) {
    if (o.quiet) return {};
    return fmt::format("wrote {} ({}x{})\n", shown_output_path(path), width, height);
}

}  // namespace fortu
