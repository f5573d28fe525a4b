#pragma once
// Validation metrics: an error against experiments or an exact solution, computed from the
// state at requested output times. A metric belongs to a scene (by name); the registry in
// metric_registry.cpp says which scenes have one, so the harness can name a metric's columns
// before any run starts and runs that ask for no validation never build one.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "io/snapshot_writer.hpp"
#include "scenes/scene.hpp"

namespace sph {

class ValidationMetric {
public:
    virtual ~ValidationMetric() = default;
    // Values of the sample columns for the state at one output time (NaN where undefined,
    // e.g. outside the range of the reference data).
    virtual std::vector<double> sample(const SnapshotData& state) = 0;
    // Values of the summary columns over every sample taken so far.
    virtual std::vector<double> summary() const = 0;
};

struct ValidationMetricInfo {
    std::string scene;        // the scene this metric validates
    std::string description;  // one line: what it measures, against what
    std::vector<std::string> sample_columns;   // per output time (the harness adds step and time)
    std::vector<std::string> summary_columns;  // one value per run (runs.csv)
    // Throws InputError when the scene's options do not fit the reference (e.g. geometry).
    std::function<std::unique_ptr<ValidationMetric>(const Scene&)> make;
};

// Every registered metric.
const std::vector<ValidationMetricInfo>& validation_metrics();
// The metric of a scene, or nullptr when it has none.
const ValidationMetricInfo* find_validation_metric(const std::string& scene);

// A metric whose samples are independent errors (an exact solution at each time): its summary
// is each column's last value ("<col>_final") and largest absolute value ("<col>_max").
// Registering such a metric is a line in metric_registry.cpp.
std::vector<std::string> pointwise_summary_columns(const std::vector<std::string>& sample_columns);
std::unique_ptr<ValidationMetric> make_pointwise_metric(
    std::size_t columns, std::function<std::vector<double>(const SnapshotData&)> evaluate);

}  // namespace sph
