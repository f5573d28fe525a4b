#pragma once
// Still water in a tank (scene `tank`): the fluid particles' pressure against the hydrostatic
// rho0 g (H - z), H the free surface the scene records.
#include "validation/validation_metric.hpp"

namespace sph {

struct HydrostaticError {
    double rel_rms = 0;     // sqrt(sum (p - p_ref)^2 / sum p_ref^2) over fluid particles
    double bottom_rel = 0;  // (mean p - mean p_ref) / mean p_ref over the lowest fluid layer
    double bottom_pa = 0;   // mean p - mean p_ref over the lowest fluid layer, Pa
    double mean_pa = 0;     // mean p - p_ref over all fluid particles, Pa (delta-SPH's offset)
};

HydrostaticError hydrostatic_error(const SnapshotData& state, double rho0, double g, double surface, double dp);

// Sample columns hydro_rel_rms, hydro_bottom_rel, hydro_bottom_pa, hydro_mean_pa; summary:
// each one's last value (after settling: the run's end) and largest magnitude.
const ValidationMetricInfo& hydrostatic_pressure_metric();

}  // namespace sph
