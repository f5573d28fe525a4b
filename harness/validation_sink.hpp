#pragma once
// The scene's validation metric (validation_recorder.hpp) on the state at the start, at every
// output time and at the last step; its samples written to a CSV when the run ends.
#include <string>
#include <utility>
#include <vector>

#include "provenance.hpp"
#include "step_sink.hpp"
#include "validation_recorder.hpp"

namespace sph {

class ValidationSink final : public StepSink {
public:
    // path "": sample, write nothing (a rank that does not write). Throws InputError when the
    // scene has no metric.
    ValidationSink(const Scene& scene, const ValidationRequest& request, std::string path, Metadata metadata)
        : recorder_(scene, request), path_(std::move(path)), metadata_(std::move(metadata)) {}
    void begin(Simulation& sim) override { recorder_.sample(sim.snapshot()); }
    void after_step(Simulation& sim, const StepRecord& r, const StepPoint& at) override;
    void end(Simulation&) override;

    const std::vector<std::pair<std::string, double>>& summary() const { return summary_; }
    const std::string& file() const { return written_; }  // "" until written
    double seconds() const { return seconds_; }  // wall time of the samples after the start

private:
    ValidationRecorder recorder_;
    std::string path_, written_;
    Metadata metadata_;
    std::vector<std::pair<std::string, double>> summary_;
    double seconds_ = 0;
};

}  // namespace sph
