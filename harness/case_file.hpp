#pragma once
// Case files: a scene as data instead of C++ (solver/scenes/box_case.hpp), in TOML, parsed
// strictly; and the scene a run names: a scene of the catalogue or "case:FILE".
//
//   [case]
//   description = "..."              # optional
//   dp = 0.0055                      # required; lattice spacing (m); --set dp=... overrides it
//   domain = [[-0.02, -0.02, -0.02], [3.24, 1.02, 1.5]]  # optional; default: the tank and its
//                                    #   walls plus one spacing on every side
//   domain_top = 1.5                 # optional, instead of `domain`: the default domain's top
//   kernel = "wendland"              # optional scene options, as --set gives them (which overrides
//   c0_factor = 20                   #   them): kernel, c0_factor (c0 = c0_factor sqrt(g H), H the
//                                    #   highest water above the floor), alpha, delta, gravity,
//                                    #   rho0, coef_h, cfl
//   [case.tank]                      # required: box walls of boundary particles, a body
//   min = [0, 0, 0]                  #   inner faces (m); the lattice's origin is `min`
//   max = [3.22, 1.0, 1.0]
//   open_top = true                  #   optional, default true
//   layers = 2                       #   optional, 1..5, default 2: wall layers, outward
//   name = "tank"                    #   optional, default "tank": the body's name
//   [[case.fluid]]                   # boxes of fluid, inside the tank
//   min = [1.992, 0, 0]
//   max = [3.22, 1.0, 0.55]
//   hydrostatic = true               #   optional, default true: density from the depth below the
//                                    #   box's free surface (half a spacing above its top layer)
//   velocity = [0, 0, 0]             #   optional (m/s)
//   [[case.obstacle]]                # solid boxes, each a named body, inside the tank (an open
//   name = "box"                     #   tank's obstacle may rise above its top); required name
//   min = [0.6635, 0.295, 0]
//   max = [0.8245, 0.698, 0.161]
//   layers = 2                       #   optional, 1..5, default the tank's: shell layers, inward
//   [[case.mesh]]                    # a closed OBJ mesh filled with fluid (at rest, rho0)
//   file = "bunny.obj"               #   required; found as scene meshes are (find_mesh)
//   height = 0.3                     #   required (m): scaled to this along its up axis
//   min = [0.5, 0.2, 0.1]            #   required: where its bounding box's low corner goes
//   up = "y"                         #   optional, "y" (rotated to z, the paper's meshes) or "z"
//   [[case.gauges]]                  # gauges every run of the case samples, as DualSPHysics'
//   kind = "pressure"                #   case XML carries its gauges: the keys of a spec's
//   name = "P1"                      #   [[gauges]] (gauge_options.hpp); unnamed: KIND<n>
//   x = 0.8395                       #   counting that kind in the case; a force gauge's body
//   y = 0.4965                       #   must be one of the case's
//   z = 0.021
//   every = 0.001
//
// A run samples the case's gauges first, in the case's order; a gauge of the run's own (a
// spec's [[gauges]], --gauge) with a case gauge's name takes that gauge's place (say, P1 at
// every step, or moved), and the run's other gauges come after (merge_gauges).
//
// Refused with "FILE:LINE: ..." naming the key: an unknown key, a wrong type, max not above
// min, a fluid box or obstacle outside the tank, a fluid box overlapping an obstacle, two
// bodies of one name, a gauge of an unknown kind, with an unknown or missing key, a gauge
// name used twice, a force gauge on no body of the case; and when built, a box smaller than
// one spacing (and by the run, a gauge outside the scene's domain: check_gauge).
#include <string>
#include <vector>

#include "gauge.hpp"
#include "scenes/box_case.hpp"
#include "solver_settings.hpp"

namespace sph {

// Throws InputError naming the file, the line and the key of any problem.
BoxCase load_case_file(const std::string& path);
// A "case:FILE" scene's [[case.gauges]], named, in the file's order (the file read and checked
// as load_case_file checks it); no gauges for any other scene. Throws InputError.
std::vector<Gauge> case_gauges(const std::string& scene);

constexpr const char* case_scene_prefix = "case:";
bool is_case_scene(const std::string& scene);
std::string case_file_of(const std::string& scene);  // "case:FILE" -> FILE

// What every run is built from: a scene of the catalogue by name, or a case file's scene
// ("case:FILE", its provenance carrying the file's hash). Throws InputError.
Scene build_scene(const std::string& scene, const SettingMap& options);

// A file-name-safe stem for a scene's outputs: its name, or a case file's stem.
std::string scene_stem(const std::string& scene);

}  // namespace sph
