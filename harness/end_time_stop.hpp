#pragma once
// Stops a run at the first step that reaches a simulated time: validation runs and stability
// trials compare runs over the same stretch of the flow, whatever their time steps.
#include "stop_rule.hpp"

namespace sph {

class EndTimeStop final : public StopRule {
public:
    explicit EndTimeStop(double end_time) : end_time_(end_time) {}
    bool reached(const Simulation& sim) override { return sim.time() >= end_time_; }
    double end_time() const { return end_time_; }

private:
    double end_time_;
};

}  // namespace sph
