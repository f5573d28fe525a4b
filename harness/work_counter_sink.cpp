#include "work_counter_sink.hpp"

namespace sph {

void WorkCounterSink::count(Simulation& sim) {
    const WorkCounters w = sim.count_work();
    totals_.candidates += w.candidates;
    totals_.neighbours += w.neighbours;
    totals_.ranges += w.ranges;
    ++totals_.samples;
}

void WorkCounterSink::after_step(Simulation& sim, const StepRecord&, const StepPoint& at) {
    if (!at.recorded) return;
    if (every_ > 0) {
        if (at.recorded_step % every_ == 0) count(sim);
        return;
    }
    ended_recorded_ = at.last;
}

void WorkCounterSink::end(Simulation& sim) {
    if (every_ == 0 && ended_recorded_) count(sim);
}

}  // namespace sph
