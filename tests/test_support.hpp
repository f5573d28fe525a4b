#pragma once
// Small scenes built directly in tests (no lattice, no walls), and a brute-force reference.
#include <algorithm>
#include <cmath>
#include <random>

#include "scenes/scene.hpp"
#include "gauge.hpp"
#include "simulation.hpp"

namespace sph::test {

// n particles uniformly in a cube of side `side` at `corner`, jittered lattice-free random
// positions; the first n_boundary are boundary particles. Domain = cube grown by `margin`.
inline Scene random_scene(std::size_t n, std::size_t n_boundary, double side, double dp, unsigned seed,
                          double margin = 0.0, double speed = 0.0) {
    Scene s;
    s.name = "random";
    s.dp = dp;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, side), v(-speed, speed), r(0.99, 1.01);
    for (std::size_t i = 0; i < n; ++i) {
        s.position.push_back({u(rng), u(rng), u(rng)});
        s.velocity.push_back({float(i < n_boundary ? 0 : v(rng)), float(i < n_boundary ? 0 : v(rng)),
                              float(i < n_boundary ? 0 : v(rng))});
        s.density.push_back(float(1000 * r(rng)));
    }
    s.n_boundary = n_boundary;
    s.params.rho0 = 1000;
    s.params.h = real(std::sqrt(3.0) * dp);
    s.params.mass = real(1000 * dp * dp * dp);
    s.params.c0 = 10;
    s.params.alpha = real(0.1);
    s.params.delta = real(0.1);
    s.params.gravity = {0, 0, 0};
    s.params = finish_params(s.params);
    s.kernel = KernelType::wendland;
    s.lo = {-margin, -margin, -margin};
    s.hi = {side + margin, side + margin, side + margin};
    return s;
}

// A small dam break (a 0.6 m column in a 1.0 x 0.2 x 0.8 m tank) at spacing dp.
inline Scene small_dambreak(const char* dp) {
    return make_scene("dambreak", {{"dp", dp}, {"length", "1.0"}, {"column_height", "0.6"}, {"height", "0.8"}});
}

// Absolute positions of a snapshot, indexed by particle id.
inline std::vector<std::array<double, 3>> positions_by_id(const SnapshotData& s) {
    std::vector<std::array<double, 3>> out(s.id.size());
    for (std::size_t i = 0; i < s.id.size(); ++i)
        out[s.id[i]] = {s.position[3 * i], s.position[3 * i + 1], s.position[3 * i + 2]};
    return out;
}

// Steps two simulations side by side.
inline void step_both(Simulation& a, Simulation& b, int steps) {
    for (int k = 0; k < steps; ++k) {
        a.step();
        b.step();
    }
}

// The largest coordinate difference between two runs' fluid particles (ids from n_boundary
// on), with `shift` subtracted from the second run's positions first.
inline double largest_fluid_difference(const std::vector<std::array<double, 3>>& a,
                                       const std::vector<std::array<double, 3>>& b, std::size_t n_boundary,
                                       double shift = 0) {
    double worst = 0;
    for (std::size_t i = n_boundary; i < a.size(); ++i)
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs((b[i][k] - shift) - a[i][k]));
    return worst;
}

// A gauge at (x, y, z) with the other keys at their defaults.
inline Gauge gauge_at(GaugeKind kind, const std::string& name, double x, double y, double z = 0) {
    Gauge g;
    g.kind = kind;
    g.name = name;
    g.x = x;
    g.y = y;
    g.z = z;
    return g;
}

}  // namespace sph::test
