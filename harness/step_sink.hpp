#pragma once
// What a run loop (run_loop.hpp) feeds with the state and the step records: the step table,
// the work counters, snapshots, the validation metric, the energy monitor, the progress line,
// the last good state of a blow-up. Each sink is told the start, every step, a blow-up and
// the end; it keeps what it gathers for its owner to read. A run that fails gets no end().
#include <string>

#include "simulation.hpp"

namespace sph {

struct StepPoint {
    long step = 0;           // steps taken, warm-up included (1-based)
    long recorded_step = 0;  // steps taken after the warm-up (<= 0 during it)
    bool recorded = false;   // past the warm-up
    bool last = false;       // a stop rule ends the run after this step
};

class StepSink {
public:
    virtual ~StepSink() = default;
    // The state before the first step.
    virtual void begin(Simulation&) {}
    virtual void after_step(Simulation& sim, const StepRecord& record, const StepPoint& at) = 0;
    // The solver's blow-up check fired; a sink that keeps the state appends where to `where`
    // ("; the last good state is in ...").
    virtual void blow_up(const BlowUpError&, std::string& /*where*/) {}
    // The run ended: a stop rule was reached, or a blow-up was recorded.
    virtual void end(Simulation&) {}
};

}  // namespace sph
