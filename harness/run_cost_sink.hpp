#pragma once
// What a whole run costs, over every step from the start (warm-up included): the steps, and
// with Verlet lists which of them rebuilt the lists and the wall clock of those steps and of
// the others (listed steps). A step rebuilt the lists when the simulation's count of list
// builds grew during it. The means are of the steps' own wall clocks (StepRecord::wall_ms).
#include <cmath>
#include <limits>

#include "step_sink.hpp"

namespace sph {

struct RunCost {
    long steps = 0;          // every step, warm-up included
    long rebuild_steps = 0;  // steps that built neighbour lists
    double rebuild_wall_ms = 0, listed_wall_ms = 0;  // the sums of their wall clocks

    long listed_steps() const { return steps - rebuild_steps; }
    // Means in milliseconds; NaN where there was no such step.
    double rebuild_step_ms() const { return mean(rebuild_wall_ms, rebuild_steps); }
    double listed_step_ms() const { return mean(listed_wall_ms, listed_steps()); }

private:
    static double mean(double sum, long n) { return n > 0 ? sum / double(n) : std::numeric_limits<double>::quiet_NaN(); }
};

class RunCostSink final : public StepSink {
public:
    void begin(Simulation& sim) override { builds_ = sim.neighbour_list_builds(); }
    void after_step(Simulation& sim, const StepRecord& r, const StepPoint&) override {
        ++cost_.steps;
        const long builds = sim.neighbour_list_builds();
        if (builds != builds_) {
            ++cost_.rebuild_steps;
            cost_.rebuild_wall_ms += r.wall_ms;
        } else {
            cost_.listed_wall_ms += r.wall_ms;
        }
        builds_ = builds;
    }
    const RunCost& cost() const { return cost_; }

private:
    long builds_ = 0;
    RunCost cost_;
};

}  // namespace sph
