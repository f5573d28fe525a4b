#pragma once
// Picks the fastest neighbour-search strategy for a scene on this machine: a few steps of
// each (CLL, Cell Merging, Smaller Cell n = 2..4, with and without merging), timed, and the
// one with the shortest median step wins (beyond the paper, which fixes n = 2 with merging).
#include <vector>

#include "simulation.hpp"

namespace sph {

struct CalibrationTrial {
    SearchOptions search;
    double median_step_ms = 0;
};

struct Calibration {
    SearchOptions best;
    std::vector<CalibrationTrial> trials;
};

Calibration calibrate_search(const Scene& scene, const SolverOptions& base, int steps = 8);

}  // namespace sph
