#include "run_loop.hpp"

#include <chrono>

namespace sph {

bool RunLoop::reached() const {
    for (StopRule* r : rules_)
        if (r->reached(sim_)) return true;
    return false;
}

RunLoopOutcome RunLoop::run() {
    RunLoopOutcome out;
    for (StepSink* s : sinks_) s->begin(sim_);
    const auto t0 = std::chrono::steady_clock::now();
    bool stop = reached();
    try {
        while (!stop) {
            const StepRecord& r = sim_.step();
            stop = reached();
            StepPoint at;
            at.step = r.step;
            at.recorded_step = r.step - warmup_;
            at.recorded = at.recorded_step > 0;
            at.last = stop;
            for (StepSink* s : sinks_) s->after_step(sim_, r, at);
        }
    } catch (const BlowUpError& e) {
        std::string where;
        for (StepSink* s : sinks_) s->blow_up(e, where);
        bool recorded = false;
        for (StopRule* r : rules_) recorded = recorded || r->ends_on_blow_up();
        if (!recorded) {
            if (!where.empty()) throw RunError(std::string(e.what()) + where);
            throw;
        }
        out.blow_up = BlowUpRecord{e.what(), where, e.step, e.particle, e.quantity};
    }
    out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.steps = sim_.steps_taken();
    out.time = sim_.time();
    for (StepSink* s : sinks_) s->end(sim_);
    return out;
}

}  // namespace sph
