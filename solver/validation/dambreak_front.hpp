#pragma once
// The surge front of a collapsing water column (scene `dambreak`) against Martin and Moyce
// (1952) and Koshizuka and Oka (1996), in their non-dimensional form: Z = x / a against
// T = t sqrt(2 g / a), a the column's width and its height 2a (Martin and Moyce's n^2 = 2).
#include <memory>

#include "validation/validation_metric.hpp"

namespace sph {

// The front: the largest x of a fluid particle within `band` of the floor (z = floor_z) that
// has another fluid particle within 2 dp. The neighbour test drops single droplets thrown
// ahead of the surge, which a camera tracking the leading edge of the water would not follow.
// Returns NaN when no fluid particle is on the floor.
double surge_front_x(const SnapshotData& state, double dp, double floor_z, double band);

// Sample columns: T, Z, Z_martin_moyce, Z_koshizuka_oka (the data interpolated at T; NaN
// outside the data's T range). Summary: front_rms_martin_moyce, front_max_martin_moyce,
// front_rms_koshizuka_oka, front_max_koshizuka_oka (RMS and largest |Z - Z_data| over the
// samples where the data are defined), front_T_end (the last sample's T).
const ValidationMetricInfo& dambreak_front_metric();

}  // namespace sph
