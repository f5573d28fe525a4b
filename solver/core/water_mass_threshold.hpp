#pragma once
// Where kernel-summed fluid mass counts as water, as DualSPHysics' water-level gauge decides it:
// a point is in the water when sum_j m W(|x - x_j|, h) over fluid j reaches half a particle's
// mass per particle volume, 0.5 m / dp^3 (its 3D mass limit; inside the water the sum is about
// m / dp^3 = rho0, on a free surface about half that). The water_level gauge (solver/gauge.cpp)
// reads a vertical line with it from the bottom up (first_threshold_crossing); the dam-break
// front (validation/dambreak_front.cpp) reads the floor's line from its far end (the last one). One definition, so that the two measure water the same way.
#include <cmath>
#include <cstddef>
#include <limits>

namespace sph {

inline double water_mass_threshold(double particle_mass, double dp) {
    return 0.5 * particle_mass / (dp * dp * dp);
}

// A line sampled at first + spacing k, k = 0 .. count - 1, with summed mass mass_at(k): the
// coordinate of the last sample at or above the threshold, moved towards the next sample by
// linear interpolation to where the sum crosses the threshold (the last sample itself when it is
// the line's end). NaN when no sample reaches it.
template <class MassAt>
double last_threshold_crossing(std::size_t count, double first, double spacing, double threshold, MassAt&& mass_at) {
    for (std::size_t k = count; k-- > 0;) {
        const double here = mass_at(k);
        if (!(here >= threshold)) continue;
        const double at = first + spacing * double(k);
        if (k + 1 == count) return at;
        const double next = mass_at(k + 1);
        return at + spacing * (here - threshold) / (here - next);
    }
    return std::numeric_limits<double>::quiet_NaN();
}

// The same line read from its first sample up, as DualSPHysics' water-level gauge reads it
// (JGaugeSwl: the first point where the sum falls below the limit after one at or above it):
// the first wet-to-dry crossing, linearly interpolated between the two samples; the line's last
// sample when it stays wet to its end; NaN when no sample reaches the threshold. Spray or a
// jet above the water body (a splash off an obstacle) does not lift the level, as it would
// read from the top down.
template <class MassAt>
double first_threshold_crossing(std::size_t count, double first, double spacing, double threshold, MassAt&& mass_at) {
    bool wet = false;
    double previous = 0;
    for (std::size_t k = 0; k < count; ++k) {
        const double here = mass_at(k);
        if (here >= threshold) {
            wet = true;
        } else if (wet) {
            return first + spacing * (double(k - 1) + (previous - threshold) / (previous - here));
        }
        previous = here;
    }
    return wet ? first + spacing * double(count - 1) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace sph
