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
