#include "work_counter_sink.hpp"

namespace sph {

void WorkCounterSink::after_step(Simulation& sim, const StepRecord&, const StepPoint& at) {
    if (!at.recorded) return;
    const bool count = every_ > 0 ? at.recorded_step % every_ == 0 : at.step == budget_last_step_;
    if (!count) return;
    const WorkCounters w = sim.count_work();
    totals_.candidates += w.candidates;
    totals_.neighbours += w.neighbours;
    totals_.ranges += w.ranges;
    ++totals_.samples;
}

}  // namespace sph
