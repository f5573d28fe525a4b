#pragma once
// The phases of a step. One table gives each phase the name used both for its timer column
// and for its NVTX range, so that Nsight timelines and CSV columns always agree.
#include <array>
#include <cstddef>

namespace sph {

enum class Phase : int { neighbour_list = 0, forces, integrate, diagnostics, exchange, migrate, balance, count };

constexpr std::size_t phase_count = std::size_t(Phase::count);

constexpr std::array<const char*, phase_count> phase_names = {
    "neighbour_list", "forces", "integrate", "diagnostics", "exchange", "migrate", "balance"};

constexpr const char* phase_name(Phase p) { return phase_names[std::size_t(p)]; }

// In multi-subdomain runs, "exchange" is the one exchange per step (migration and ghosts
// together, with its sort) and "migrate" the drop of stale ghosts at the start of the step.
// With the overlap of paper section 5.3, "exchange" is the host's time to issue the exchange
// after the inner update is queued (on the CUDA backend the copies run on the transport's
// streams, under that update), and its sort is the next step's "neighbour_list".
using PhaseTimes = std::array<double, phase_count>;  // milliseconds

// The paper's "update of physical quantities": forces plus integration.
inline double update_time(const PhaseTimes& t) {
    return t[std::size_t(Phase::forces)] + t[std::size_t(Phase::integrate)];
}

// Times phases on whatever clock the backend has (CUDA events on the subdomain's stream,
// a steady clock on the host). Begin/end pairs may repeat within a step; they add up.
class PhaseClock {
public:
    virtual ~PhaseClock() = default;
    virtual void begin(Phase p) = 0;
    virtual void end(Phase p) = 0;
    // Waits for the step's work and returns the accumulated times, then resets them.
    virtual PhaseTimes collect() = 0;
};

// A clock that measures nothing: passes meant for a profiler, where events would only add noise.
class NullPhaseClock final : public PhaseClock {
public:
    void begin(Phase) override {}
    void end(Phase) override {}
    PhaseTimes collect() override { return PhaseTimes{}; }
};

}  // namespace sph
