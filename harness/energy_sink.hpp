#pragma once
// The energy monitor (energy_monitor.hpp): the energy budget and the free surface of the
// state at the start, every `every` steps and at the last step.
#include <vector>

#include "energy_monitor.hpp"
#include "step_sink.hpp"

namespace sph {

class EnergySink final : public StepSink {
public:
    EnergySink(const Scene& scene, long every, std::vector<EnergySample>& samples)
        : scene_(scene), every_(every), samples_(samples) {}
    void begin(Simulation& sim) override { sample(sim); }
    void after_step(Simulation& sim, const StepRecord&, const StepPoint& at) override {
        if (at.step % every_ == 0 || at.last) sample(sim);
    }

private:
    void sample(Simulation& sim) { samples_.push_back(measure_energy(sim.snapshot(), scene_.params, scene_.dp)); }
    const Scene& scene_;
    long every_;
    std::vector<EnergySample>& samples_;
};

}  // namespace sph
