#pragma once
// The deterministic work counters (candidate pairs, neighbour pairs, ranges), counted on
// recorded steps: every `every`-th one, or with every = 0 once, on the last step of the step
// budget. A run that an end time stops before its budget is spent has no counts (the accuracy
// study's runs.csv leaves the counter columns empty): counting costs a step's work again.
#include "step_sink.hpp"

namespace sph {

struct WorkTotals {
    unsigned long long candidates = 0, neighbours = 0, ranges = 0;
    long samples = 0;  // how many steps were counted
};

class WorkCounterSink final : public StepSink {
public:
    WorkCounterSink(long every, long budget_last_step) : every_(every), budget_last_step_(budget_last_step) {}
    void after_step(Simulation& sim, const StepRecord& r, const StepPoint& at) override;
    const WorkTotals& totals() const { return totals_; }

private:
    long every_, budget_last_step_;
    WorkTotals totals_;
};

}  // namespace sph
