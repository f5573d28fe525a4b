#pragma once
// Phase timing on the host's steady clock: the host backend's clock, and the clock of the
// host-side phases of multi-device runs (exchange, migration, balancing).
#include <chrono>

#include "backend/phase.hpp"

namespace sph {

class SteadyPhaseClock final : public PhaseClock {
public:
    void begin(Phase p) override { start_[std::size_t(p)] = std::chrono::steady_clock::now(); }
    void end(Phase p) override {
        const auto dt = std::chrono::steady_clock::now() - start_[std::size_t(p)];
        times_[std::size_t(p)] += std::chrono::duration<double, std::milli>(dt).count();
    }
    PhaseTimes collect() override {
        PhaseTimes t = times_;
        times_.fill(0);
        return t;
    }

private:
    std::array<std::chrono::steady_clock::time_point, phase_count> start_{};
    PhaseTimes times_{};
};

}  // namespace sph
