#include "search_calibration.hpp"

#include "statistics.hpp"

namespace sph {

Calibration calibrate_search(const Scene& scene, const SolverOptions& base, int steps) {
    Calibration c;
    double best = 1e300;
    for (int n = 1; n <= 4; ++n)
        for (bool merge : {false, true}) {
            SolverOptions o = base;
            o.search = SearchOptions{n, merge};
            Simulation sim(scene, o);
            sim.step();  // the first step carries one-off costs
            std::vector<double> ms;
            for (int k = 0; k < steps; ++k) ms.push_back(sim.step().step_ms());
            const CalibrationTrial t{o.search, summarize(ms).median};
            c.trials.push_back(t);
            if (t.median_step_ms < best) {
                best = t.median_step_ms;
                c.best = t.search;
            }
        }
    return c;
}

}  // namespace sph
