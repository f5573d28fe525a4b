#pragma once
// The stability studies' runs: one trial (does the scene reach a simulated time without the
// solver's blow-up check firing?), the bisection over the CFL number built on it, and a long
// run that samples the energy budget and the free surface on the way.
//
// Criterion: a trial is stable when it reaches `time` seconds of simulated time (or, with
// time = 0, `max_steps` steps) without a BlowUpError; the check runs on every step and fires
// on a non-finite acceleration or density rate, a fluid speed above c0, or a fluid density
// outside [0.5, 2] rho0. A fixed simulated time, not a fixed step count, so that a small CFL
// is not judged on a shorter stretch of the flow than a large one.
#include <cstdint>
#include <string>
#include <vector>

#include "energy_monitor.hpp"
#include "simulation.hpp"
#include "step_sink.hpp"

namespace sph {

struct TrialTarget {
    double time = 0;      // simulated seconds to reach; 0: max_steps steps
    long max_steps = 0;   // a trial that needs more steps than this is an input error (0 with a time: no cap)
    bool progress = false;
};

struct TrialOutcome {
    double cfl = 0;
    bool stable = false;
    long steps = 0;        // steps completed
    double time = 0;       // simulated time reached
    double wall_s = 0;
    long failed_step = 0;  // the rest: only when it blew up
    std::uint32_t particle = 0;
    std::string quantity, message;
};

// Runs one trial on the run loop (run_loop.hpp) and feeds its steps to `sinks` (an energy
// monitor, the last good state). Throws InputError when the target needs more than max_steps
// steps, RunError for anything but a blow-up.
TrialOutcome run_trial(const Scene& scene, const SolverOptions& solver, const TrialTarget& target,
                       const std::vector<StepSink*>& sinks);
// The same with an energy monitor: `sample_every` > 0 samples the state every that many steps
// (and at step 0 and the last step) into `samples`.
TrialOutcome run_trial(const Scene& scene, const SolverOptions& solver, const TrialTarget& target,
                       long sample_every = 0, std::vector<EnergySample>* samples = nullptr);

struct CflLimit {
    double stable = 0;    // largest CFL found stable (0: even cfl_low blew up)
    double unstable = 0;  // smallest CFL found unstable (0: even cfl_high was stable)
    std::vector<TrialOutcome> trials;  // in the order they ran
};

// Bisection in log(cfl) between low and high: high first (it usually fails at once), then
// low, then `bisections` midpoints. The limit lies in [stable, unstable].
CflLimit find_cfl_limit(const Scene& scene, SolverOptions solver, const TrialTarget& target, double low, double high,
                        long bisections);

}  // namespace sph
