// How long Verlet lists could live (issue 25: the rebuilds of a whole run). The solver rebuilds
// when a bound on the largest displacement since the build, sum over steps of dt (v_max +
// dt a_max / 2) from the step statistics, passes half the skin (Simulation::verlet_list_expired).
// The exact condition is the largest displacement itself: while every particle has moved at
// most half the skin, every pair now inside the support was within support + skin at the build.
// On one trajectory (the solver's own, host backend) this counts the rebuilds the exact
// condition would make: a virtual build is taken at each point where the largest displacement
// since the last virtual build passes half the skin; the physics does not depend on when the
// lists are rebuilt (they always hold every pair inside the support), so one run serves both.
//   list_life SCENE END_TIME SKIN [KEY=VALUE ...]   (scene options, e.g. dp=0.02 kernel=wendland)
// Prints one CSV row a real rebuild (the step, the steps the list lived, the largest real
// displacement at the last step that reused it and at the state it was rebuilt from, as
// fractions of half the skin) and a summary line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scenes/scene.hpp"
#include "simulation.hpp"

namespace {

// Positions by particle id.
std::vector<double> by_id(const sph::SnapshotData& s) {
    std::vector<double> p(s.position.size());
    for (std::size_t k = 0; k < s.id.size(); ++k)
        for (int a = 0; a < 3; ++a) p[3 * std::size_t(s.id[k]) + a] = s.position[3 * k + a];
    return p;
}

double largest_displacement(const std::vector<double>& now, const std::vector<double>& then) {
    double d2 = 0;
    for (std::size_t i = 0; i + 2 < now.size(); i += 3) {
        const double dx = now[i] - then[i], dy = now[i + 1] - then[i + 1], dz = now[i + 2] - then[i + 2];
        d2 = std::max(d2, dx * dx + dy * dy + dz * dz);
    }
    return std::sqrt(d2);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: list_life SCENE END_TIME SKIN [KEY=VALUE ...]\n");
        return 2;
    }
    try {
        std::map<std::string, std::string> options;
        for (int k = 4; k < argc; ++k) {
            const std::string kv = argv[k];
            const auto eq = kv.find('=');
            if (eq == std::string::npos) throw sph::InputError("list_life: '" + kv + "' is not KEY=VALUE");
            options[kv.substr(0, eq)] = kv.substr(eq + 1);
        }
        const sph::Scene scene = sph::make_scene(argv[1], options);
        const double end_time = std::atof(argv[2]);
        sph::SolverOptions o;
        o.search.cells_per_support = 2;
        o.search.verlet = true;
        o.search.skin = std::atof(argv[3]);
        sph::Simulation sim(scene, o);
        const double half_skin = 0.5 * o.search.skin * scene.params.support;
        std::vector<double> real_build = by_id(sim.snapshot()), virtual_build = real_build, before = real_build;
        long builds = sim.neighbour_list_builds(), virtual_builds = 1, last_build_step = 0, steps = 0;
        double last_moved = 0, reused_moved = 0, sum_fraction = 0, worst_reused = 0;
        std::printf("build_step,time,steps_lived,last_reused_over_half_skin,rebuilt_from_over_half_skin\n");
        while (sim.time() < end_time) {
            sim.step();
            ++steps;
            const std::vector<double> now = by_id(sim.snapshot());
            if (sim.neighbour_list_builds() != builds) {  // this step rebuilt, from the state before it
                std::printf("%ld,%.5f,%ld,%.4f,%.4f\n", sim.steps_taken(), sim.time(), sim.steps_taken() - last_build_step,
                            reused_moved / half_skin, last_moved / half_skin);
                sum_fraction += reused_moved / half_skin;
                builds = sim.neighbour_list_builds();
                last_build_step = sim.steps_taken();
                real_build = before;  // the step sorted and built on the state before its update
            } else {
                reused_moved = last_moved;  // this step's forces were taken there, with the old lists
                worst_reused = std::max(worst_reused, reused_moved / half_skin);
            }
            last_moved = largest_displacement(now, real_build);
            if (largest_displacement(now, virtual_build) > half_skin) {  // the next step would rebuild from now
                ++virtual_builds;
                virtual_build = now;
            }
            before = now;
        }
        const long real_builds = sim.neighbour_list_builds();
        std::printf("# %ld steps to %.4f s, skin %.3g of the support: %ld builds by the bound (every %.2f steps), "
                    "%ld by the largest displacement (every %.2f steps); at the last step a list served, the particles had "
                    "moved %.3f of half the skin on average, %.4f at most\n",
                    steps, sim.time(), o.search.skin, real_builds, double(steps) / real_builds, virtual_builds,
                    double(steps) / virtual_builds, sum_fraction / std::max(1L, real_builds - 1), worst_reused);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "list_life: %s\n", e.what());
        return 2;
    }
    return 0;
}
