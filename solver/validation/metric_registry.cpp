// Which scene has which validation metric. Adding one is a line here (and its file).
#include "validation/dambreak_front.hpp"
#include "validation/hydrostatic_pressure.hpp"
#include "validation/taylor_green.hpp"
#include "validation/validation_metric.hpp"

namespace sph {

const std::vector<ValidationMetricInfo>& validation_metrics() {
    static const std::vector<ValidationMetricInfo> metrics = {
        dambreak_front_metric(),
        hydrostatic_pressure_metric(),
        {"taylor-green", "velocity L2 error and energy decay against the exact solution",
         {"velocity_l2", "energy_decay_error"},
         pointwise_summary_columns({"velocity_l2", "energy_decay_error"}),
         [](const Scene& scene) {
             return make_pointwise_metric(2, [scene](const SnapshotData& s) {
                 const TaylorGreenError e = taylor_green_error(s, scene);
                 return std::vector<double>{e.velocity_l2, e.energy_decay_error};
             });
         }},
    };
    return metrics;
}

const ValidationMetricInfo* find_validation_metric(const std::string& scene) {
    for (const auto& m : validation_metrics())
        if (m.scene == scene) return &m;
    return nullptr;
}

}  // namespace sph
