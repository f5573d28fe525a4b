#pragma once
// The progress line of a run on a terminal (progress.hpp), updated every `every` steps: the
// step, the simulated time (and the end time when there is one), and how far the run is
// towards whichever of its step cap and end time it reaches first.
#include <string>

#include "progress.hpp"
#include "step_sink.hpp"

namespace sph {

class ProgressSink final : public StepSink {
public:
    // total_steps: the step budget or cap, warm-up included (0: none); end_time: 0 for none.
    // with_update_time: the line shows the step's update time too.
    ProgressSink(std::string label, long total_steps, double end_time, bool enabled, long every = 1,
                 bool with_update_time = true)
        : progress_(std::move(label), enabled), total_(total_steps), end_time_(end_time), every_(every),
          with_update_time_(with_update_time) {}
    ~ProgressSink() override { finish(); }
    void after_step(Simulation& sim, const StepRecord& r, const StepPoint& at) override;
    void blow_up(const BlowUpError&, std::string&) override { finish(); }
    void end(Simulation&) override { finish(); }

private:
    void finish() {
        if (!finished_) progress_.finish();
        finished_ = true;
    }
    Progress progress_;
    long total_;
    double end_time_;
    long every_;
    bool with_update_time_;
    bool finished_ = false;
};

}  // namespace sph
