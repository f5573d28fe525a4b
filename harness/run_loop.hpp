#pragma once
// The one step loop of `run`, `simulate` and `stability`: steps a simulation until a stop
// rule (stop_rule.hpp) is reached, feeding every step to the sinks (step_sink.hpp). What
// ends a run and what is made of its steps are the rules and sinks given; the loop itself
// only orders them.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "simulation.hpp"
#include "step_sink.hpp"
#include "stop_rule.hpp"

namespace sph {

// A blow-up that a stop rule (RecordBlowUp) took as the run's end.
struct BlowUpRecord {
    std::string message;  // the solver's sentence
    std::string where;    // where the last good state went ("" when no sink kept it)
    long step = 0;        // the step that failed
    std::uint32_t particle = 0;
    std::string quantity;
};

struct RunLoopOutcome {
    long steps = 0;      // steps completed, warm-up included
    double time = 0;     // simulated time reached
    double wall_seconds = 0;  // the steps and the sinks' work on them; not begin() or end()
    std::optional<BlowUpRecord> blow_up;
};

class RunLoop {
public:
    // `warmup` steps come first and are not recorded (StepPoint::recorded).
    explicit RunLoop(Simulation& sim, long warmup = 0) : sim_(sim), warmup_(warmup) {}

    // Rules are asked in the order added; sinks are told in the order added. Neither is owned.
    RunLoop& stop_when(StopRule& rule) {
        rules_.push_back(&rule);
        return *this;
    }
    RunLoop& feed(StepSink& sink) {
        sinks_.push_back(&sink);
        return *this;
    }

    // Throws what a rule throws (InputError), and the blow-up when no rule ends the run on it:
    // a RunError naming where the last good state went when a sink kept it, else the
    // BlowUpError itself. Anything else the solver throws passes through.
    RunLoopOutcome run();

private:
    bool reached() const;

    Simulation& sim_;
    long warmup_;
    std::vector<StopRule*> rules_;
    std::vector<StepSink*> sinks_;
};

}  // namespace sph
