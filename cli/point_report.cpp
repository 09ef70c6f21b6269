// cli/point_report.cpp — the lines of `fortu eval` and `:eval`, written once for both.
#include "cli/point_report.hpp"

#include "interp/gradient_check.hpp"
#include "runtime/fv_model.hpp"

#include <cmath>
#include <fmt/format.h>

namespace fortu {

std::string point_report(const Model& model, std::array<double, 3> p, const Engine& engine, const Grid& grid) {
    const PointValue v = evaluate_point(model, p, engine);
    const int dims = model.dims();
    const double h[3] = {grid.x.step() > 0 ? grid.x.step() : 1.0, grid.y.step() > 0 ? grid.y.step() : 1.0,
                         grid.z.step() > 0 ? grid.z.step() : 1.0};
    auto value_at = [&](double dx, double dy, double dz) {
        return evaluate_point(model, {p[0] + dx, p[1] + dy, p[2] + dz}, engine).value;
    };
    std::string out = fmt::format("value: {}\n", v.value);

    bool gradient_finite = true;
    for (int k = 0; k < dims; ++k) gradient_finite = gradient_finite && std::isfinite(v.gradient[k]);
    // A valid value without a finite gradient (SQRT at 0, a corner): say where it breaks
    // rather than print NaNs.
    if (!gradient_finite && std::isfinite(v.value)) {
        const std::optional<UndefinedGradient> cause = find_undefined_gradient(model.graph, model.root, p);
        out += cause ? fmt::format("gradient: undefined ({})\n", describe(*cause)) : "gradient: undefined\n";
    } else {
        out += "gradient:";
        for (int k = 0; k < std::max(dims, 2); ++k) out += fmt::format(" {}", v.gradient[k]);
        out += '\n';
    }

    std::vector<double> n;
    if (dims == 3) {
        const auto n5 = fv_hyperplane({p[0], p[1], p[2], v.value}, {p[0] + h[0], p[1], p[2], value_at(h[0], 0, 0)},
                                      {p[0], p[1] + h[1], p[2], value_at(0, h[1], 0)},
                                      {p[0], p[1], p[2] + h[2], value_at(0, 0, h[2])});
        n.assign(n5.begin(), n5.end());
    } else {
        const auto n4 = fv_plane({p[0], p[1], v.value}, {p[0] + h[0], p[1], value_at(h[0], 0, 0)},
                                 {p[0], p[1] + h[1], value_at(0, h[1], 0)});
        n.assign(n4.begin(), n4.end());
    }
    out += "normal:";
    for (std::size_t k = 0; k < n.size(); ++k) out += fmt::format(" n{}={}", k + 1, n[k]);
    out += '\n';
    out += fmt::format("inside: {}\n", v.value > 0 ? "yes" : v.value == 0 ? "boundary" : std::isfinite(v.value) ? "no" : "invalid");
    return out;
}

}  // namespace fortu
