#pragma once
// Gauges as the user writes them: `--gauge KIND:key=value,...` on `sphbench simulate`, a
// spec's [[gauges]] tables, or a case file's [[case.gauges]] tables (kind, name and the same
// keys; gauge_tables.hpp reads both). Keys per kind:
//   pressure, velocity  x, y, z        water_level  x, y        max_height  x, y, radius
//   force               body           every kind:  every (simulated seconds, > 0), name
// Parsed strictly: an unknown kind or key, a missing one, a value that is not a number, a
// name used twice: InputError naming it. Whether the gauge fits the scene is checked against
// the scene (solver/gauge.hpp: check_gauge).
//
// A run of a case file samples the case's gauges and the request's (the spec's or --gauge's):
// the case's first, in the case's order; a request gauge whose name is a case gauge's takes
// that gauge's place (a spec samples the case's P1 at every step, or moves it, by naming it
// P1); the request's other gauges come after (merge_gauges). Unnamed gauges are named last.
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
// The gauges a run samples: `from_case` (a case file's, case_gauges; empty for other scenes),
// each replaced in place by the `requested` gauge of its name, then the other requested gauges
// in their order; named by name_gauges. Throws InputError for a name the request gives twice.
std::vector<Gauge> merge_gauges(const std::vector<Gauge>& from_case, const std::vector<Gauge>& requested);

}  // namespace sph
