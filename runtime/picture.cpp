// runtime/picture.cpp — colour map, contour marking and the 8-bit OpenImageIO writer.
#include "runtime/picture.hpp"

#include "runtime/output_path.hpp"
#include "runtime/picture_legend.hpp"
#include "runtime/output_error.hpp"

#include "runtime/image_io.hpp"
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>

namespace fortu {
namespace {

constexpr std::size_t kScaleSample = 1'000'000;

std::uint8_t blend(std::uint8_t near, std::uint8_t far, double t, double shade) {
    const double v = (near + (far - near) * t) * shade;
    return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
}

// The 99th percentile of positive magnitudes (0 if there are none).
double percentile_99(std::vector<double>& magnitudes) {
    if (magnitudes.empty()) return 0.0;
    const auto at = magnitudes.begin() + static_cast<std::ptrdiff_t>(0.99 * (magnitudes.size() - 1));
    std::nth_element(magnitudes.begin(), at, magnitudes.end());
    return *at;
}

int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

std::span<const double> slice_values(const Field& field, int slice) {
    const std::size_t per_slice = static_cast<std::size_t>(field.grid.cols()) * field.grid.rows();
    return std::span<const double>(field.values).subspan(slice * per_slice, per_slice);
}

void write_one_slice(const Field& field, int slice, const ColourScale& scale, const std::string& path,
                     const OutputOptions& options) {
    Picture picture{field.grid.cols(), field.grid.rows(), render_slice(field, slice, scale, options)};
    if (options.picture.legend)
        picture = add_legend(picture, field.grid, slice, scale, picture_levels(scale, options.picture), options.picture);
    static_assert(sizeof(Rgb8) == 3);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(picture.pixels.data());
    write_image_8bit(path, picture.cols, picture.rows, 3,
                     std::span<const std::uint8_t>(bytes, picture.pixels.size() * 3), options);
}

}  // namespace

ColourScale colour_scale(std::span<const double> values) {
    const std::size_t stride = std::max<std::size_t>(1, values.size() / kScaleSample);
    std::vector<double> inside, outside;
    inside.reserve(values.size() / stride + 1);   // untouched until written: no regrowth copies
    outside.reserve(values.size() / stride + 1);
    for (std::size_t i = 0; i < values.size(); i += stride) {
        if (values[i] > 0.0 && std::isfinite(values[i])) inside.push_back(values[i]);
        if (values[i] < 0.0 && std::isfinite(values[i])) outside.push_back(-values[i]);
    }
    const double in = percentile_99(inside), out = percentile_99(outside);
    const double fallback = in > 0.0 ? in : (out > 0.0 ? out : 1.0);
    return {in > 0.0 ? in : fallback, out > 0.0 ? out : fallback};
}

ColourScale picture_colour_scale(std::span<const double> values, const ScaleChoice& choice) {
    switch (choice.mode) {
        case ScaleChoice::Mode::Auto: return colour_scale(values);
        case ScaleChoice::Mode::Fixed: return {choice.high, -choice.low};
        case ScaleChoice::Mode::Symmetric: break;
    }
    const std::size_t stride = std::max<std::size_t>(1, values.size() / kScaleSample);
    std::vector<double> magnitudes;
    for (std::size_t i = 0; i < values.size(); i += stride)
        if (values[i] != 0.0 && std::isfinite(values[i])) magnitudes.push_back(std::abs(values[i]));
    const double both = percentile_99(magnitudes);
    return {both > 0.0 ? both : 1.0, both > 0.0 ? both : 1.0};
}

std::vector<double> picture_levels(const ColourScale& scale, const PictureStyle& style) {
    std::vector<double> levels;
    if (!style.levels.empty()) {
        for (double v : style.levels)
            if (v != 0.0) levels.push_back(v);
    } else {
        for (int k = 1; k <= style.level_count; ++k) levels.push_back(-scale.outside * k / style.level_count);
        for (int k = 1; k <= style.level_count; ++k) levels.push_back(scale.inside * k / style.level_count);
    }
    std::sort(levels.begin(), levels.end());
    return levels;
}

Rgb8 value_colour(double value, const ColourScale& scale, int bands) {
    if (!std::isfinite(value)) return kInvalidColour;
    const bool inside = value >= 0.0;
    const double relative = std::abs(value) / (inside ? scale.inside : scale.outside);
    const double t = std::min(relative, 1.0);
    // Bands: a soft dark stripe every 1/bands of the scale, level sets made visible.
    const double shade =
        bands > 0 ? 1.0 - 0.15 * (0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * bands * relative)) : 1.0;
    const Rgb8 near = inside ? kInsideNear : kOutsideNear;
    const Rgb8 far = inside ? kInsideFar : kOutsideFar;
    return {blend(near.r, far.r, t, shade), blend(near.g, far.g, t, shade), blend(near.b, far.b, t, shade)};
}

int picture_slice(const Grid& grid, int requested) {
    if (grid.dims != 3) return requested <= 0 ? 0 : -1;
    if (requested == -1) return grid.slices() / 2;
    return requested >= 0 && requested < grid.slices() ? requested : -1;
}

namespace {
/// A red ring of radius ~4 px around each marker, so the point itself stays visible.
void draw_markers(const Grid& g, const std::vector<std::array<double, 2>>& markers, int cols, int rows,
                  std::vector<Rgb8>& pixels) {
    constexpr Rgb8 kMarkerColour{220, 20, 20};
    const double hx = g.x.step() > 0 ? g.x.step() : 1.0, hy = g.y.step() > 0 ? g.y.step() : 1.0;
    for (const auto& m : markers) {
        const double fc = (m[0] - g.x.min) / hx, fr = (g.y.max - m[1]) / hy;
        if (!(fc > -4 && fc < cols + 4 && fr > -4 && fr < rows + 4)) continue;
        for (int r = static_cast<int>(fr) - 6; r <= static_cast<int>(fr) + 6; ++r)
            for (int c = static_cast<int>(fc) - 6; c <= static_cast<int>(fc) + 6; ++c) {
                const double d = std::hypot(c - fc, r - fr);
                if (c < 0 || c >= cols || r < 0 || r >= rows || d < 3.0 || d > 4.6) continue;
                pixels[static_cast<std::size_t>(r) * cols + c] = kMarkerColour;
            }
    }
}
}  // namespace

std::vector<Rgb8> render_slice(const Field& field, int slice, const ColourScale& scale,
                               const OutputOptions& options) {
    const Grid& g = field.grid;
    const std::span<const double> v = slice_values(field, slice);
    const int cols = g.cols(), rows = g.rows();
    std::vector<double> levels = picture_levels(scale, options.picture);   // sorted
    if (options.draw_contour) levels.insert(std::lower_bound(levels.begin(), levels.end(), 0.0), 0.0);
    std::vector<Rgb8> pixels(v.size());
    // Neighbouring pixels often hold the same value (a sign picture holds three): its colour
    // is computed once per run of equal values, not per pixel.
    std::uint64_t last_bits = std::bit_cast<std::uint64_t>(v.empty() ? 0.0 : v[0]) ^ 1u;
    Rgb8 last_colour{};
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const std::size_t i = static_cast<std::size_t>(r) * cols + c;
            const std::uint64_t bits = std::bit_cast<std::uint64_t>(v[i]);
            if (bits != last_bits) {
                last_bits = bits;
                last_colour = value_colour(v[i], scale, options.bands);
            }
            pixels[i] = last_colour;
            if (!std::isfinite(v[i]) || levels.empty()) continue;
            // A level can be marked here only if it lies between this value and a finite
            // neighbour's (or equals this value): the levels outside that span are skipped.
            // (std::min and std::max keep the first argument against a NaN; an infinite
            // neighbour only widens the span, and the test below excludes it.)
            double low = v[i], high = v[i];
            auto widen = [&](double w) {
                low = std::min(low, w);
                high = std::max(high, w);
            };
            if (c > 0 && c + 1 < cols && r > 0 && r + 1 < rows) {
                widen(v[i - 1]);
                widen(v[i + 1]);
                widen(v[i - cols]);
                widen(v[i + cols]);
            } else {
                if (c > 0) widen(v[i - 1]);
                if (c + 1 < cols) widen(v[i + 1]);
                if (r > 0) widen(v[i - cols]);
                if (r + 1 < rows) widen(v[i + cols]);
            }
            auto first = std::lower_bound(levels.begin(), levels.end(), low);
            if (first == levels.end() || *first > high) continue;
            // On the level set of `level`: exactly there, or the nearer side of a sign change.
            auto on_level = [&](double level) {
                const double here = v[i] - level;
                if (here == 0.0) return true;
                auto crosses = [&](int cc, int rr) {
                    if (cc < 0 || cc >= cols || rr < 0 || rr >= rows) return false;
                    const double w = v[static_cast<std::size_t>(rr) * cols + cc] - level;
                    return std::isfinite(w) && sign_of(w) == -sign_of(here) && std::abs(w) >= std::abs(here);
                };
                return crosses(c - 1, r) || crosses(c + 1, r) || crosses(c, r - 1) || crosses(c, r + 1);
            };
            bool on_other_level = false, on_contour = false;
            for (auto level = first; level != levels.end() && *level <= high; ++level) {
                if (!on_level(*level)) continue;
                // Zero is the contour when it is drawn (it is never among picture_levels).
                if (*level == 0.0 && options.draw_contour) on_contour = true;
                else on_other_level = true;
            }
            if (on_other_level) pixels[i] = kLevelColour;
            if (on_contour) pixels[i] = kContourColour;
        }
    draw_markers(g, options.markers, cols, rows, pixels);
    return pixels;
}

void write_image_8bit(const std::string& path, int cols, int rows, int channels,
                      std::span<const std::uint8_t> pixels, const OutputOptions& options) {
    static const char* kNames[] = {"R", "G", "B", "A"};
    ImageLayer layer;
    layer.cols = cols;
    layer.rows = rows;
    if (channels == 1) layer.channels = {"Y"};
    else
        for (int c = 0; c < channels; ++c) layer.channels.push_back(c < 4 ? kNames[c] : fmt::format("c{}", c));
    layer.pixels = pixels.data();
    layer.text_attributes.emplace_back("Software", "fortu");
    const std::string ext = path_extension(path);
    if (ext == "jpg" || ext == "jpeg")
        layer.text_attributes.emplace_back("Compression", fmt::format("jpeg:{}", std::clamp(options.jpeg_quality, 1, 100)));
    write_image_file(path, {layer});
}

void write_picture(const Field& field, const OutputTarget& target, const OutputOptions& options) {
    const Grid& g = field.grid;
    if (g.dims == 3 && target.series) {
        const ColourScale scale = picture_colour_scale(field.values, options.picture.scale);
        for (int s = 0; s < g.slices(); ++s) write_one_slice(field, s, scale, target.file(s), options);
        return;
    }
    const int slice = picture_slice(g, options.slice);
    if (slice < 0)
        throw OutputError(target.path, fmt::format("slice {} is out of range 0..{}", options.slice, g.slices() - 1));
    write_one_slice(field, slice, picture_colour_scale(slice_values(field, slice), options.picture.scale),
                    target.file(slice), options);
}

}  // namespace fortu
