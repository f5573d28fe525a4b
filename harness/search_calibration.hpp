#pragma once
// Picks the fastest neighbour-search strategy for a scene on this machine: a few steps of
// each (CLL, Cell Merging, Smaller Cell n = 2..4, with and without merging, and Verlet lists
// on cells of the support and on half-size cells), timed, and the one with the shortest mean
// step wins (beyond the paper, which fixes n = 2 with merging).
#include <string>
#include <vector>

#include "simulation.hpp"

namespace sph {

struct CalibrationTrial {
    SearchOptions search;
    double mean_step_ms = 0;
};

struct Calibration {
    SearchOptions best;
    std::vector<CalibrationTrial> trials;
    // Why the Verlet lists were not timed (on several subdomains they run on the host without
    // overlap only so far, and not with shifting or short periodic boxes); empty when they were.
    std::string verlet_skipped;
};

// The Verlet lists' trials rebuild every verlet_trial_rebuild_every steps and time a whole
// number of such cycles, so that their mean carries the rebuilds' cost.
constexpr int verlet_trial_rebuild_every = 5;

Calibration calibrate_search(const Scene& scene, const SolverOptions& base, int steps = 8);

// "n2m" for n = 2 with merging, "v2" for Verlet lists on half-size cells: the trial's name.
std::string search_label(const SearchOptions& s);

}  // namespace sph
