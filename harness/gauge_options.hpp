#pragma once
// Gauges as the user writes them: `--gauge KIND:key=value,...` on `sphbench simulate`, or a
// spec's [[gauges]] tables (kind, name and the same keys). Keys per kind:
//   pressure, velocity  x, y, z        water_level  x, y        max_height  x, y, radius
//   force               body           every kind:  every (simulated seconds, > 0), name
// Parsed strictly: an unknown kind or key, a missing one, a value that is not a number, a
// name used twice: InputError naming it. Whether the gauge fits the scene is checked against
// the scene (solver/gauge.hpp: check_gauge).
#include <map>
#include <string>
#include <vector>

#include "gauge.hpp"

namespace sph {

// `where` names the source in messages ("--gauge 'water_level:x=1'", "spec.toml:12: [[gauges]]").
Gauge make_gauge(const std::string& kind, const std::map<std::string, std::string>& keys, const std::string& where);
// "KIND:key=value,key=value".
Gauge parse_gauge_option(const std::string& text);
// Gives unnamed gauges the name KIND<n> (n counting that kind from 1) and refuses a name used twice.
void name_gauges(std::vector<Gauge>& gauges);

}  // namespace sph
