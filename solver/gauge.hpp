#pragma once
// Gauges as a user places them (in metres, in the scene's frame), and how each becomes probes
// the backends sum (physics/gauges.hpp) and, from their summed partial sums, the values of
// its columns in <run>_gauges.csv:
//   pressure NAME     (Pa) at (x, y, z): Shepard-normalised kernel interpolation over fluid
//   velocity NAME_x, NAME_y, NAME_z (m/s) at (x, y, z): likewise
//   water_level NAME  (m, height) on the vertical line (x, y): as DualSPHysics' swl gauge,
//                     the line sampled every dp / 2 from the domain's bottom to its top; the
//                     level is where the kernel-summed fluid mass sum m W first falls, from
//                     the bottom up, below half a particle's mass per particle volume
//                     (0.5 m / dp^3, as core/water_mass_threshold.hpp defines it for every
//                     user), linearly interpolated between the two samples (spray above the
//                     water does not lift it); nan on a dry line
//   max_height NAME   (m) the highest fluid particle within `radius` of the line (x, y)
//   force NAME_x, NAME_y, NAME_z (N) the fluid's force on the scene's body `body`
// A gauge with no fluid where it looks reads nan.
#include <string>
#include <vector>

#include "neighbours/grid.hpp"
#include "physics/gauges.hpp"
#include "scenes/scene.hpp"

namespace sph {

struct Gauge {
    GaugeKind kind = GaugeKind::pressure;
    std::string name;
    double x = 0, y = 0, z = 0, radius = 0;
    std::string body;
    double every = 0;  // simulated seconds between samples (the harness's to honour)
};

const char* gauge_kind_name(GaugeKind kind);
// Throws InputError for an unknown name, listing the kinds.
GaugeKind gauge_kind(const std::string& name);
std::vector<std::string> gauge_columns(const Gauge& g);
// Throws InputError, naming the gauge, for a point outside the scene's domain, an unknown
// body or a radius that is not positive.
void check_gauge(const Gauge& g, const Scene& scene);
// The probes of a gauge in the grid's frame (a water level: one per sample of its line).
std::vector<GaugeProbe> gauge_probes(const Gauge& g, const Scene& scene, const Grid& grid);
// The gauge's column values from its probes' partial sums, summed over every subdomain.
std::vector<double> gauge_values(const Gauge& g, const Scene& scene, const Grid& grid, const GaugeSum* sums);

}  // namespace sph
