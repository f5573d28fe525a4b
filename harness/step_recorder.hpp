#pragma once
// Keeps the record of every step after the warm-up: what the summaries and the step table
// are made of.
#include <vector>

#include "step_sink.hpp"

namespace sph {

class StepRecorder final : public StepSink {
public:
    void after_step(Simulation&, const StepRecord& r, const StepPoint& at) override {
        if (at.recorded) records_.push_back(r);
    }
    const std::vector<StepRecord>& records() const { return records_; }
    std::vector<StepRecord> take() { return std::move(records_); }

private:
    std::vector<StepRecord> records_;
};

}  // namespace sph
