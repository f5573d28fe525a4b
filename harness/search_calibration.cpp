#include "search_calibration.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "core/error.hpp"

#include "statistics.hpp"

namespace sph {

namespace {

// The lists' layouts and skins tried: cells of the support at the skin the benchmarks took
// for them, and half-size cells over the range the whole events were measured at (0.05 to
// 0.2; beyond it a rebuild's cost grows faster than the steps it saves).
struct ListTrial {
    int cells_per_support;
    double skin;
};
constexpr ListTrial list_trials[] = {{1, 0.1}, {2, 0.05}, {2, 0.1}, {2, 0.2}};

SearchOptions verlet_trial(const ListTrial& t) {
    SearchOptions s;
    s.cells_per_support = t.cells_per_support;
    s.verlet = true;
    s.skin = t.skin;
    s.rebuild_every = verlet_trial_rebuild_every;
    return s;
}

}  // namespace

std::string search_label(const SearchOptions& s) {
    if (s.verlet) {
        char skin[32];
        std::snprintf(skin, sizeof skin, "%g", s.skin);
        return "v" + std::to_string(s.cells_per_support) + "s" + skin;
    }
    return "n" + std::to_string(s.cells_per_support) + (s.merge ? "m" : "");
}

double expected_rebuild_interval(const PhysicsParams& p, double cfl, double skin) {
    const double v = 0.1 * double(p.c0);
    const double dt = cfl * double(p.h) / (double(p.c0) + v);
    return std::max(1.0, 0.5 * skin * double(p.support) / (v * dt));
}

double predicted_step_ms(double rebuild_step_ms, double listed_step_ms, double rebuild_interval) {
    return listed_step_ms + (rebuild_step_ms - listed_step_ms) / std::max(1.0, rebuild_interval);
}

Calibration calibrate_search(const Scene& scene, const SolverOptions& base, int steps) {
    Calibration c;
    std::vector<SearchOptions> candidates;
    for (int n = 1; n <= 4; ++n)
        for (bool merge : {false, true}) candidates.push_back(SearchOptions{n, merge});
    for (const ListTrial& t : list_trials) candidates.push_back(verlet_trial(t));
    // A whole number of rebuild cycles for the lists (at least two).
    const int cycle = verlet_trial_rebuild_every;
    const int verlet_steps = std::max(2, (steps + cycle - 1) / cycle) * cycle;
    const double cfl = base.cfl > 0 ? base.cfl : scene.cfl;
    double best = 1e300;
    for (const SearchOptions& search : candidates) {
        SolverOptions o = base;
        o.search = search;
        if (search.verlet && !c.verlet_skipped.empty()) continue;
        std::vector<double> ms, rebuild_ms, listed_ms;
        try {
            Simulation sim(scene, o);
            sim.step();  // the first step carries one-off costs (and builds the lists)
            for (int k = 0; k < (search.verlet ? verlet_steps : steps); ++k) {
                const long builds = sim.neighbour_list_builds();
                const double step_ms = sim.step().step_ms();
                ms.push_back(step_ms);
                (sim.neighbour_list_builds() > builds ? rebuild_ms : listed_ms).push_back(step_ms);
            }
        } catch (const std::runtime_error& e) {
            // A cell search refused is the run's own error; the lists may be refused where the
            // cell search is not (shifting, a short periodic box, a grid too large for the
            // GPU's cell coordinates).
            if (!search.verlet || !(dynamic_cast<const InputError*>(&e) || dynamic_cast<const RunError*>(&e))) throw;
            c.verlet_skipped = e.what();
            continue;
        }
        CalibrationTrial t{search, summarize(ms).mean};
        if (search.verlet && !rebuild_ms.empty() && !listed_ms.empty()) {
            t.rebuild_step_ms = summarize(rebuild_ms).mean;
            t.listed_step_ms = summarize(listed_ms).mean;
            t.rebuild_interval = expected_rebuild_interval(scene.params, cfl, search.skin);
            t.mean_step_ms = predicted_step_ms(t.rebuild_step_ms, t.listed_step_ms, t.rebuild_interval);
        }
        c.trials.push_back(t);
        if (t.mean_step_ms < best) {
            best = t.mean_step_ms;
            c.best = t.search;
        }
    }
    // The run keeps the skin but rebuilds when its own flow needs it.
    c.best.rebuild_every = base.search.rebuild_every;
    return c;
}

}  // namespace sph
