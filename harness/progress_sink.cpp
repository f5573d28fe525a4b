#include "progress_sink.hpp"

#include <algorithm>
#include <cstdio>

namespace sph {

void ProgressSink::after_step(Simulation&, const StepRecord& r, const StepPoint& at) {
    if (at.step % every_ != 0 && !at.last) return;
    double fraction = 0;
    if (total_ > 0) fraction = double(at.step) / double(total_);
    if (end_time_ > 0) fraction = std::max(fraction, r.time / end_time_);
    char detail[160];
    int n = total_ > 0 ? std::snprintf(detail, sizeof detail, "step %ld/%ld", at.step, total_)
                       : std::snprintf(detail, sizeof detail, "step %ld", at.step);
    n += end_time_ > 0 ? std::snprintf(detail + n, sizeof detail - std::size_t(n), ", t = %.4f of %.4g s", r.time, end_time_)
                       : std::snprintf(detail + n, sizeof detail - std::size_t(n), ", t = %.4f s", r.time);
    if (with_update_time_) std::snprintf(detail + n, sizeof detail - std::size_t(n), ", %.2f ms/step", r.update_ms());
    progress_.update(at.last ? 1.0 : fraction, detail);
}

}  // namespace sph
