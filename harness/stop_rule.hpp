#pragma once
// When a run loop (run_loop.hpp) ends. Each rule is asked before the first step and after
// every step whether the run has reached it; the first that has ends the run there. When the
// solver's blow-up check fires, the run fails unless a rule takes the blow-up as the run's end
// (a result of a study). Rules: StepCountStop (a step budget), EndTimeStop (a simulated time),
// RecordBlowUp (the blow-up policy).
#include "simulation.hpp"

namespace sph {

class StopRule {
public:
    virtual ~StopRule() = default;
    // True ends the run with the steps taken so far. May throw InputError when the rule's
    // target can no longer be met.
    virtual bool reached(const Simulation& sim) = 0;
    // True: a blow-up ends the run and is recorded in its outcome; false (every rule): it fails.
    virtual bool ends_on_blow_up() const { return false; }
};

}  // namespace sph
