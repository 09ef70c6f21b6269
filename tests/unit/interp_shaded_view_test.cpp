// tests/unit/interp_shaded_view_test.cpp — shaded views against the exact picture of a sphere:
// which pixels are hit, each hit's depth and its normal, for the sphere written as a
// polynomial and through exp and ln (whose leaves' float32 search is SLEEF's, not libm's).
#include "interp_test_support.hpp"

#include "interp/shaded_view.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace fortu;

namespace {

constexpr double kRadius = 0.6;
/// Pixels whose ray meets the sphere this close to its silhouette (z below this) are only
/// checked for being hit: grazing rays cross the surface over several samples.
constexpr double kRim = 0.3;

struct SphereErrors {
    int wrong_hits = 0;         ///< pixels hit where the ray misses the sphere, or missed where it meets it
    double depth_samples = 0;   ///< the largest depth error, in depth samples
    double normal = 0;          ///< the largest error of a normal's component
};

/// Renders `text` (a sphere of radius kRadius about the origin, positive inside) from the front
/// on size × size pixels over [-1, 1]³ and compares each pixel with the exact sphere.
SphereErrors compare_with_sphere(const std::string& text, int size) {
    test::Compiled c = test::compile_text(text);
    REQUIRE(c.model);
    const std::array<AxisRange, 3> box{};
    const SurfaceImage image = render_shaded_view(c.model->graph, c.model->root, box, ViewDirection{0, 0}, size, size);
    // Front: from +Z, X to the right, Y up; depth sample k at z = 1 - k × step (shaded_view.hpp).
    const double step = 2.0 / (size - 1);
    const int last_sample = static_cast<int>(std::ceil(2.0 / step));
    SphereErrors e;
    for (int row = 0; row < size; ++row)
        for (int col = 0; col < size; ++col) {
            const std::size_t i = std::size_t(row) * size + col;
            const double x = -1 + col * step, y = 1 - row * step, r2 = x * x + y * y;
            const double z = std::sqrt(std::max(0.0, kRadius * kRadius - r2));
            if (r2 >= kRadius * kRadius) {
                e.wrong_hits += image.hit[i] != SurfaceImage::Hit::None;
                continue;
            }
            if (z < kRim) continue;
            if (image.hit[i] != SurfaceImage::Hit::Surface) {
                ++e.wrong_hits;
                continue;
            }
            const double k = (1 - z) / step;
            e.depth_samples = std::max(e.depth_samples, std::abs(image.depth[i] * last_sample - k));
            const double exact[3] = {x / kRadius, y / kRadius, z / kRadius};
            for (int a = 0; a < 3; ++a) e.normal = std::max(e.normal, std::abs(image.normal[i][a] - exact[a]));
        }
    return e;
}

}  // namespace

TEST_CASE("a shaded view of a sphere has the exact hits, depths and normals") {
    const char* spheres[] = {
        "ARGUMENT X, Y, Z\nRETURN 0.36 - X*X - Y*Y - Z*Z",
        "ARGUMENT X, Y, Z\nRETURN EXP(-3 * (X*X + Y*Y + Z*Z)) - EXP(-1.08)",
        "ARGUMENT X, Y, Z\nRETURN LN(1 + EXP(3 - 5 * SQRT(X*X + Y*Y + Z*Z))) - LN(2)",
    };
    for (const char* text : spheres)
        for (int size : {64, 256}) {
            CAPTURE(text);
            CAPTURE(size);
            const SphereErrors e = compare_with_sphere(text, size);
            MESSAGE("depth error ", e.depth_samples, " samples, normal error ", e.normal);
            CHECK(e.wrong_hits == 0);
            // Newton from the float32 bracket: within 5% of a sample (hits at a leaf's first
            // sample start a whole sample away); the normal is the gradient there, so off by
            // at most the angle that a sample's step subtends on the sphere.
            CHECK(e.depth_samples < 0.05);
            CHECK(e.normal < 2.0 / (size - 1) / kRadius);
        }
}

TEST_CASE("a shaded view of a sphere partly in front of another shows the nearer surface at every pixel") {
    // Regions along the front sphere's silhouette are partly hit early: the rest of their
    // pixels (shrunk to their own box) must still find the sphere behind, at its depth.
    struct Sphere {
        double x, y, z, r;
    };
    const Sphere spheres[] = {{0.0, 0.0, -0.2, 0.6}, {0.3, 0.25, 0.45, 0.3}};
    test::Compiled c = test::compile_text(
        "ARGUMENT X, Y, Z\n"
        "RETURN MAX(0.36 - X*X - Y*Y - (Z + 0.2)*(Z + 0.2), 0.09 - (X - 0.3)*(X - 0.3) - (Y - 0.25)*(Y - 0.25) - (Z - 0.45)*(Z - 0.45))");
    REQUIRE(c.model);
    const int size = 128;
    const SurfaceImage image =
        render_shaded_view(c.model->graph, c.model->root, std::array<AxisRange, 3>{}, ViewDirection{0, 0}, size, size);
    const double step = 2.0 / (size - 1);
    const int last_sample = static_cast<int>(std::ceil(2.0 / step));
    int wrong_hits = 0, checked = 0;
    double depth_error = 0;
    for (int row = 0; row < size; ++row)
        for (int col = 0; col < size; ++col) {
            const std::size_t i = std::size_t(row) * size + col;
            const double x = -1 + col * step, y = 1 - row * step;
            // The nearest front surface (largest z) among the spheres the ray meets, and how
            // far inside the nearest sphere's silhouette the ray is (grazing rays are skipped).
            double front = -1e9, margin = 0;
            int nearest = -1;
            for (int k = 0; k < 2; ++k) {
                const Sphere& s = spheres[k];
                const double r2 = (x - s.x) * (x - s.x) + (y - s.y) * (y - s.y);
                if (r2 >= s.r * s.r) continue;
                const double z = s.z + std::sqrt(s.r * s.r - r2);
                if (z > front) front = z, margin = std::sqrt(s.r * s.r - r2), nearest = k;
            }
            if (front == -1e9) {
                wrong_hits += image.hit[i] != SurfaceImage::Hit::None;
                continue;
            }
            // Near the crease where the spheres meet, the samples before the hit may belong to
            // the other sphere (MAX switches between them): only the hit is checked there.
            const Sphere& other = spheres[1 - nearest];
            const double to_other = std::sqrt((x - other.x) * (x - other.x) + (y - other.y) * (y - other.y) +
                                              (front - other.z) * (front - other.z)) - other.r;
            if (margin < 0.15 || to_other < 3 * step) {
                wrong_hits += image.hit[i] == SurfaceImage::Hit::None;
                continue;
            }
            if (image.hit[i] != SurfaceImage::Hit::Surface) {
                ++wrong_hits;
                continue;
            }
            ++checked;
            depth_error = std::max(depth_error, std::abs(image.depth[i] * last_sample - (1 - front) / step));
        }
    CHECK(wrong_hits == 0);
    CHECK(checked > 3000);
    CHECK(depth_error < 0.05);
}
