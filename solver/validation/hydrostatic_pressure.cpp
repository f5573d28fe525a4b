#include "validation/hydrostatic_pressure.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace sph {

HydrostaticError hydrostatic_error(const SnapshotData& s, double rho0, double g, double surface, double dp) {
    double z_low = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < s.type.size(); ++i)
        if (s.type[i] == 0 && std::isfinite(s.position[3 * i + 2])) z_low = std::min(z_low, s.position[3 * i + 2]);
    double diff2 = 0, ref2 = 0, diff = 0, bottom_p = 0, bottom_ref = 0;
    long n = 0, n_bottom = 0;
    for (std::size_t i = 0; i < s.type.size(); ++i) {
        const double z = s.position[3 * i + 2];
        if (s.type[i] != 0 || !std::isfinite(z)) continue;
        const double ref = rho0 * g * (surface - z), p = double(s.pressure[i]);
        diff2 += (p - ref) * (p - ref);
        ref2 += ref * ref;
        diff += p - ref;
        ++n;
        if (z < z_low + 0.5 * dp) {
            bottom_p += p;
            bottom_ref += ref;
            ++n_bottom;
        }
    }
    HydrostaticError e;
    if (n == 0) throw RunError("the hydrostatic metric found no fluid particle");
    e.rel_rms = std::sqrt(diff2 / ref2);
    e.bottom_pa = (bottom_p - bottom_ref) / double(n_bottom);
    e.bottom_rel = (bottom_p - bottom_ref) / bottom_ref;
    e.mean_pa = diff / double(n);
    return e;
}

const ValidationMetricInfo& hydrostatic_pressure_metric() {
    static const std::vector<std::string> columns = {"hydro_rel_rms", "hydro_bottom_rel", "hydro_bottom_pa",
                                                     "hydro_mean_pa"};
    static const ValidationMetricInfo info = {
        "tank",
        "fluid pressure against rho0 g (H - z): relative RMS, and the error of the bottom layer",
        columns,
        pointwise_summary_columns(columns),
        [](const Scene& scene) {
            const auto it = scene.settings.find("free_surface");
            if (it == scene.settings.end()) throw InputError("scene '" + scene.name + "' records no free surface");
            const double surface = std::stod(it->second), rho0 = scene.params.rho0, dp = scene.dp;
            const double g = -double(scene.params.gravity.z);
            return make_pointwise_metric(columns.size(), [=](const SnapshotData& s) {
                const HydrostaticError e = hydrostatic_error(s, rho0, g, surface, dp);
                return std::vector<double>{e.rel_rms, e.bottom_rel, e.bottom_pa, e.mean_pa};
            });
        },
    };
    return info;
}

}  // namespace sph
