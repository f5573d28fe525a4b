#pragma once
// The progress line of a run on a terminal (progress.hpp), updated every `every` steps.
#include <string>

#include "progress.hpp"
#include "step_sink.hpp"

namespace sph {

class ProgressSink final : public StepSink {
public:
    // with_update_time: the line shows the simulated time and the step's update time.
    ProgressSink(std::string label, long total, bool enabled, long every = 1, bool with_update_time = true)
        : progress_(std::move(label), total, enabled), every_(every), with_update_time_(with_update_time) {}
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
    long every_;
    bool with_update_time_;
    bool finished_ = false;
};

}  // namespace sph
