#include "search_calibration.hpp"

#include <stdexcept>

#include "core/error.hpp"

#include "statistics.hpp"

namespace sph {

namespace {

// The Verlet lists as the benchmarks of docs/results.md run them: cells of the support with a skin of
// 0.1 supports, and half-size cells with 0.05. They rebuild every 5 steps here, more often than
// any flow measured so far (the dam break rebuilt every 7.5 steps once its column fell, at
// 0.13 s): a cautious estimate of what the lists cost a step.
SearchOptions verlet_trial(int cells_per_support, double skin) {
    SearchOptions s;
    s.cells_per_support = cells_per_support;
    s.verlet = true;
    s.skin = skin;
    s.rebuild_every = verlet_trial_rebuild_every;
    return s;
}

}  // namespace

std::string search_label(const SearchOptions& s) {
    if (s.verlet) return "v" + std::to_string(s.cells_per_support);
    return "n" + std::to_string(s.cells_per_support) + (s.merge ? "m" : "");
}

Calibration calibrate_search(const Scene& scene, const SolverOptions& base, int steps) {
    Calibration c;
    std::vector<SearchOptions> candidates;
    for (int n = 1; n <= 4; ++n)
        for (bool merge : {false, true}) candidates.push_back(SearchOptions{n, merge});
    candidates.push_back(verlet_trial(1, 0.1));
    candidates.push_back(verlet_trial(2, 0.05));
    // A whole number of rebuild cycles for the lists (at least one).
    const int cycle = verlet_trial_rebuild_every;
    const int verlet_steps = (steps + cycle - 1) / cycle * cycle;
    double best = 1e300;
    for (const SearchOptions& search : candidates) {
        SolverOptions o = base;
        o.search = search;
        if (search.verlet && !c.verlet_skipped.empty()) continue;
        std::vector<double> ms;
        try {
            Simulation sim(scene, o);
            sim.step();  // the first step carries one-off costs (and builds the lists)
            for (int k = 0; k < (search.verlet ? verlet_steps : steps); ++k) ms.push_back(sim.step().step_ms());
        } catch (const std::runtime_error& e) {
            // A cell search refused is the run's own error; the lists may be refused where the
            // cell search is not (several subdomains overlapped, on GPUs or MPI ranks, shifting,
            // a short periodic box, a grid too large for the GPU's cell coordinates).
            if (!search.verlet || !(dynamic_cast<const InputError*>(&e) || dynamic_cast<const RunError*>(&e))) throw;
            c.verlet_skipped = e.what();
            continue;
        }
        const CalibrationTrial t{search, summarize(ms).mean};
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
