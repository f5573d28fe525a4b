#include "progress_sink.hpp"

#include <cstdio>

namespace sph {

void ProgressSink::after_step(Simulation&, const StepRecord& r, const StepPoint& at) {
    if (at.step % every_ != 0) return;
    if (!with_update_time_) return progress_.update(at.step);
    char detail[96];
    std::snprintf(detail, sizeof detail, "t = %.4f s, %.2f ms/step", r.time, r.update_ms());
    progress_.update(at.step, detail);
}

}  // namespace sph
