#pragma once
// Writes the recorded steps (a StepRecorder's) as <run>_steps.csv when the run ends, so that
// a run that fails leaves no table that looks complete.
#include <string>

#include "provenance.hpp"
#include "step_recorder.hpp"

namespace sph {

class StepCsvSink final : public StepSink {
public:
    StepCsvSink(const StepRecorder& steps, std::string path, Metadata metadata, std::size_t boundary)
        : steps_(steps), path_(std::move(path)), metadata_(std::move(metadata)), boundary_(boundary) {}
    void after_step(Simulation&, const StepRecord&, const StepPoint&) override {}
    void end(Simulation&) override;
    const std::string& path() const { return path_; }

private:
    const StepRecorder& steps_;
    std::string path_;
    Metadata metadata_;
    std::size_t boundary_;
};

}  // namespace sph
