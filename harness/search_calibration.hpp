#pragma once
// Picks the neighbour-search strategy a whole run of a scene costs least with on this machine:
// a few steps of each cell search (CLL, Cell Merging, Smaller Cell n = 2..4, with and without
// merging), timed, against Verlet lists on cells of the support and on half-size cells at
// several skins, whose rebuild steps and listed steps are timed apart and weighed by how often
// the run will rebuild (beyond the paper, which fixes n = 2 with merging).
#include <string>
#include <vector>

#include "simulation.hpp"

namespace sph {

struct CalibrationTrial {
    SearchOptions search;
    // The mean step the trial predicts for a whole run: a cell search's measured mean; the
    // lists' listed step plus their rebuild's extra cost shared over rebuild_interval steps.
    double mean_step_ms = 0;
    // Verlet lists only: the measured means of the two kinds of step, and the steps between
    // rebuilds expected of the run (expected_rebuild_interval).
    double rebuild_step_ms = 0, listed_step_ms = 0, rebuild_interval = 0;
};

struct Calibration {
    SearchOptions best;
    std::vector<CalibrationTrial> trials;
    // Why the Verlet lists were not timed (shifting, a short periodic box, a grid too large for
    // the GPU's cell coordinates); empty when they were.
    std::string verlet_skipped;
};

// The lists' trials rebuild every verlet_trial_rebuild_every steps and time a whole number of
// such cycles, so that both kinds of step are measured.
constexpr int verlet_trial_rebuild_every = 4;

// How many steps a run keeps its lists at `skin` (supports) before the skin criterion
// (Simulation::verlet_list_expired: half the skin moved) rebuilds them, when its fastest
// particle moves at the speed the scene's sound speed was chosen for: weakly compressible SPH
// takes c0 at least 10 times the largest flow speed, so c0 / 10, at the step that speed
// allows (CFL h / (c0 + v)): 55 skin / (CFL / 0.2) steps. A cautious estimate: the dam break
// 1.04M (CFL 0.2) rebuilt every 4.0, 7.7, 14.9 and 22.1 steps over its whole event at skins
// 0.05, 0.1, 0.2 and 0.3 (issue 25), where this gives 2.75, 5.5, 11 and 16.5.
double expected_rebuild_interval(const PhysicsParams& p, double cfl, double skin);

// A listed step, plus a rebuild's extra cost shared over the steps between rebuilds.
double predicted_step_ms(double rebuild_step_ms, double listed_step_ms, double rebuild_interval);

Calibration calibrate_search(const Scene& scene, const SolverOptions& base, int steps = 8);

// "n2m" for n = 2 with merging, "v2s0.1" for Verlet lists on half-size cells with a skin of
// 0.1 supports: the trial's name.
std::string search_label(const SearchOptions& s);

}  // namespace sph
