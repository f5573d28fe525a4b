#pragma once
// Validation during a run: the scene's metric (solver/validation) evaluated on the state at
// output times every `every` simulated seconds (and at the start and the end), its samples
// written to <run>_validation.csv and its summary returned for runs.csv. Nothing of this
// exists in a run that does not ask for it: no snapshot is downloaded and no metric built.
#include <memory>
#include <string>
#include <vector>

#include "provenance.hpp"
#include "validation/validation_metric.hpp"

namespace sph {

struct ValidationRequest {
    double every = 0;     // simulated seconds between output times; 0: no validation
    double end_time = 0;  // > 0: the run's end time (it stops there; steps is then a cap), in the CSV's provenance
    bool enabled() const { return every > 0; }
};

class ValidationRecorder {
public:
    // Throws InputError when the scene has no metric or does not fit its reference.
    ValidationRecorder(const Scene& scene, const ValidationRequest& request);

    // Whether the state at simulated time `time` is an output time (one is due).
    bool due(double time) const;
    // Evaluates the metric on the state and keeps the row.
    void sample(const SnapshotData& state);
    double last_sample_time() const { return last_time_; }

    const ValidationMetricInfo& info() const { return *info_; }
    std::vector<std::pair<std::string, double>> summary() const;
    // Writes every sample (step, time, then the metric's columns); returns the path.
    std::string write_csv(const std::string& path, const Metadata& metadata) const;

private:
    const ValidationMetricInfo* info_;
    std::unique_ptr<ValidationMetric> metric_;
    ValidationRequest request_;
    double next_time_ = 0, last_time_ = -1;
    std::vector<std::vector<double>> rows_;  // step, time, sample columns
};

// "dambreak, tank": the scenes that have a metric, for messages.
std::string scenes_with_validation();

}  // namespace sph
