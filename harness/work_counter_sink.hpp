#pragma once
// The deterministic work counters (candidate pairs, neighbour pairs, ranges), counted on
// recorded steps: every `every`-th one, or with every = 0 once, on the state the run ends with
// (whichever rule stopped it: a step budget or an end time). That single count is taken after
// the run loop's clock has stopped, so that counting (a step's work again) is not part of the
// run's wall time; a run that blows up has none.
#include "step_sink.hpp"

namespace sph {

struct WorkTotals {
    unsigned long long candidates = 0, neighbours = 0, ranges = 0;
    long samples = 0;  // how many steps were counted
};

class WorkCounterSink final : public StepSink {
public:
    explicit WorkCounterSink(long every) : every_(every) {}
    void after_step(Simulation& sim, const StepRecord& r, const StepPoint& at) override;
    void end(Simulation& sim) override;
    const WorkTotals& totals() const { return totals_; }

private:
    void count(Simulation& sim);
    long every_;
    bool ended_recorded_ = false;  // the last step was recorded and a rule stopped the run after it
    WorkTotals totals_;
};

}  // namespace sph
