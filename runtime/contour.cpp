// runtime/contour.cpp — marching squares over the node grid; crossing points are keyed by the
// grid edge they lie on, so neighbouring cells share them exactly and chaining is a walk over
// edge keys.
#include "runtime/contour.hpp"

#include "runtime/atomic_file.hpp"
#include "runtime/output_error.hpp"
#include "runtime/picture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace fortu {
namespace {

// A crossing point and the (at most two) segments that end at it.
struct EdgePoint {
    std::array<double, 2> xy{};
    std::array<int, 2> segments{-1, -1};
};

class ContourBuilder {
public:
    ContourBuilder(const Field& field, int slice) : field_(field), grid_(field.grid), slice_(slice) {}

    std::vector<Polyline> build() {
        for (int r = 0; r + 1 < grid_.rows(); ++r)
            for (int c = 0; c + 1 < grid_.cols(); ++c) cell(c, r);
        return chain();
    }

private:
    double value(int c, int r) const { return field_.values[grid_.index(c, r, slice_)]; }

    // Key of the edge from node (c, r) to its right (horizontal) or lower (vertical) neighbour.
    std::int64_t edge_key(int c, int r, bool vertical) const {
        return (static_cast<std::int64_t>(r) * grid_.cols() + c) * 2 + vertical;
    }

    // The crossing on an edge, always interpolated from its first node so both cells agree.
    std::int64_t crossing(int c, int r, bool vertical) {
        const std::int64_t key = edge_key(c, r, vertical);
        if (points_.contains(key)) return key;
        const int c1 = vertical ? c : c + 1, r1 = vertical ? r + 1 : r;
        const double v0 = value(c, r), v1 = value(c1, r1);
        const double t = v0 / (v0 - v1);
        const double x0 = grid_.x_at(c), y0 = grid_.y_at(r);
        EdgePoint p;
        p.xy = {x0 + t * (grid_.x_at(c1) - x0), y0 + t * (grid_.y_at(r1) - y0)};
        points_.emplace(key, p);
        return key;
    }

    void segment(std::int64_t a, std::int64_t b) {
        const int id = static_cast<int>(segments_.size());
        segments_.push_back({a, b});
        for (std::int64_t key : {a, b}) {
            auto& s = points_.at(key).segments;
            (s[0] < 0 ? s[0] : s[1]) = id;
        }
    }

    void cell(int c, int r) {
        const double tl = value(c, r), tr = value(c + 1, r), br = value(c + 1, r + 1), bl = value(c, r + 1);
        if (!std::isfinite(tl) || !std::isfinite(tr) || !std::isfinite(br) || !std::isfinite(bl)) return;
        const bool in_tl = tl >= 0, in_tr = tr >= 0, in_br = br >= 0, in_bl = bl >= 0;
        // Edges: top (tl–tr), right (tr–br), bottom (bl–br), left (tl–bl).
        std::int64_t top = -1, right = -1, bottom = -1, left = -1;
        if (in_tl != in_tr) top = crossing(c, r, false);
        if (in_tr != in_br) right = crossing(c + 1, r, true);
        if (in_bl != in_br) bottom = crossing(c, r + 1, false);
        if (in_tl != in_bl) left = crossing(c, r, true);
        const int cut = (top >= 0) + (right >= 0) + (bottom >= 0) + (left >= 0);
        if (cut == 2) {
            std::array<std::int64_t, 2> ends{};
            int n = 0;
            for (std::int64_t e : {top, right, bottom, left})
                if (e >= 0) ends[n++] = e;
            segment(ends[0], ends[1]);
        } else if (cut == 4) {
            // Saddle: the corners of the centre's sign are connected through the cell.
            const bool centre_in = (tl + tr + br + bl) / 4 >= 0;
            if (centre_in == in_tl) {   // tl and br joined: cut off tr and bl
                segment(top, right);
                segment(bottom, left);
            } else {                    // tr and bl joined: cut off tl and br
                segment(top, left);
                segment(right, bottom);
            }
        }
    }

    std::vector<Polyline> chain() {
        std::vector<bool> used(segments_.size(), false);
        std::vector<Polyline> lines;
        auto walk = [&](std::int64_t start) {
            Polyline line;
            std::int64_t at = start;
            line.points.push_back(points_.at(at).xy);
            for (;;) {
                const auto& s = points_.at(at).segments;
                const int next = s[0] >= 0 && !used[s[0]] ? s[0] : (s[1] >= 0 && !used[s[1]] ? s[1] : -1);
                if (next < 0) break;
                used[next] = true;
                at = segments_[next].first == at ? segments_[next].second : segments_[next].first;
                line.points.push_back(points_.at(at).xy);
            }
            if (at == start && line.points.size() > 2) {
                line.closed = true;
                line.points.pop_back();
            }
            lines.push_back(std::move(line));
        };
        // Open chains first, from their ends; what is left are closed loops. Keys are visited
        // in sorted order so the output does not depend on hashing.
        std::vector<std::int64_t> keys;
        keys.reserve(points_.size());
        for (const auto& [key, p] : points_) keys.push_back(key);
        std::sort(keys.begin(), keys.end());
        for (std::int64_t key : keys) {
            const auto& s = points_.at(key).segments;
            if (s[1] < 0 && s[0] >= 0 && !used[s[0]]) walk(key);
        }
        for (std::int64_t key : keys) {
            const auto& s = points_.at(key).segments;
            if ((s[0] >= 0 && !used[s[0]]) || (s[1] >= 0 && !used[s[1]])) walk(key);
        }
        return lines;
    }

    const Field& field_;
    const Grid& grid_;
    int slice_;
    std::unordered_map<std::int64_t, EdgePoint> points_;
    std::vector<std::pair<std::int64_t, std::int64_t>> segments_;
};

// Pixel coordinates of the picture fortu writes for the same grid: node (c, r) is the centre
// of pixel (c, r), so the contour lies over the PNG's contour pixels. Pixel units (not world
// units with vector-effect="non-scaling-stroke", which librsvg ignores) keep the stroke 1.5 px
// in every renderer; the world box goes into <metadata>.
void write_svg(const Field& field, int slice, const std::string& path) {
    const Grid& g = field.grid;
    const std::vector<Polyline> lines = zero_contour(field, slice);
    const int cols = g.cols(), rows = g.rows();
    const double hx = g.x.step() > 0 ? g.x.step() : 1.0, hy = g.y.step() > 0 ? g.y.step() : 1.0;
    auto pixel_x = [&](double x) { return (x - g.x.min) / hx + 0.5; };
    auto pixel_y = [&](double y) { return (g.y.max - y) / hy + 0.5; };
    fmt::memory_buffer out;
    auto put = [&out]<typename... Args>(fmt::format_string<Args...> text, Args&&... args) {
        fmt::format_to(std::back_inserter(out), text, std::forward<Args>(args)...);
    };
    put("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    put("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\">\n", cols,
        rows, cols, rows);
    put("<!-- fortu zero contour: {} polylines in pixels of the {}x{} picture (pixel centre = grid node; "
        "x = x0 + (px - 0.5) * dx, y = y1 - (py - 0.5) * dy) -->\n",
        lines.size(), cols, rows);
    put("<metadata><fortu-domain xmlns=\"urn:fortu:domain\" x0=\"{}\" x1=\"{}\" y0=\"{}\" y1=\"{}\" "
        "dx=\"{}\" dy=\"{}\"",
        g.x.min, g.x.max, g.y.min, g.y.max, hx, hy);
    if (g.dims == 3) put(" slice=\"{}\" z=\"{}\"", slice, g.z_at(slice));
    put("/></metadata>\n");
    put("<g fill=\"none\" stroke=\"black\" stroke-width=\"1.5\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n");
    for (const Polyline& line : lines) {
        put("<polyline points=\"");
        for (std::size_t i = 0; i < line.points.size(); ++i)
            put("{}{:.3f},{:.3f}", i ? " " : "", pixel_x(line.points[i][0]), pixel_y(line.points[i][1]));
        if (line.closed) put(" {:.3f},{:.3f}", pixel_x(line.points[0][0]), pixel_y(line.points[0][1]));
        put("\"/>\n");
    }
    put("</g>\n</svg>\n");
    write_file_atomically(path, [&](OutputFile& file) { file.write(out.data(), out.size()); });
}

}  // namespace

std::vector<Polyline> zero_contour(const Field& field, int slice) {
    return ContourBuilder(field, slice).build();
}

void write_contour_svg(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    const Grid& g = field.grid;
    if (g.dims == 3 && target.series) {
        for (int s = 0; s < g.slices(); ++s) write_svg(field, s, target.file(s));
        return;
    }
    const int slice = picture_slice(g, options.slice);
    if (slice < 0)
        throw OutputError(target.path, fmt::format("slice {} is out of range 0..{}", options.slice, g.slices() - 1));
    write_svg(field, slice, target.file(slice));
}

}  // namespace fortu
