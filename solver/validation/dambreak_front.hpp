#pragma once
// The surge front of a collapsing water column (scene `dambreak`) against Martin and Moyce
// (1952) and Koshizuka and Oka (1996), in their non-dimensional form: Z = x / a against
// T = t sqrt(2 g / a), a the column's width and its height 2a (Martin and Moyce's n^2 = 2).
#include <memory>

#include "validation/validation_metric.hpp"

namespace sph {

// The front: the largest x of a fluid particle within `band` of the floor (z = floor_z) that
// has another fluid particle within `radius` (the metric uses the kernel's support: a particle
// that still interacts with the water). The neighbour test drops droplets thrown ahead of the
// surge, which a camera tracking the leading edge of the water would not follow. The metric's
// band is the column's width a (the lower half of the column): the tongue's tip rides a few
// spacings above the floor at 12 spacings per column (the dynamic boundary's repulsion), and a
// band of 3 dp lost it, making the front jump back by up to 0.4 a and double the error (RMS 0.30
// instead of 0.15 against Martin and Moyce). Returns NaN when no fluid is in the band.
double surge_front_x(const SnapshotData& state, double radius, double floor_z, double band);

// Sample columns: T, Z, Z_martin_moyce, Z_koshizuka_oka (the data interpolated at T; NaN
// outside the data's T range). Summary: front_rms_martin_moyce, front_max_martin_moyce,
// front_rms_koshizuka_oka, front_max_koshizuka_oka (RMS and largest |Z - Z_data| over the
// samples where the data are defined), front_T_end (the last sample's T).
const ValidationMetricInfo& dambreak_front_metric();

}  // namespace sph
