// The generic metric for errors that each output time defines on its own (an exact solution):
// summarised by the last and the largest value of each column.
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "validation/validation_metric.hpp"

namespace sph {
namespace {

class PointwiseMetric : public ValidationMetric {
public:
    PointwiseMetric(std::size_t columns, std::function<std::vector<double>(const SnapshotData&)> evaluate)
        : evaluate_(std::move(evaluate)),
          last_(columns, std::numeric_limits<double>::quiet_NaN()),
          largest_(columns, std::numeric_limits<double>::quiet_NaN()) {}

    std::vector<double> sample(const SnapshotData& state) override {
        std::vector<double> v = evaluate_(state);
        if (v.size() != last_.size()) throw RunError("a validation metric returned the wrong number of values");
        for (std::size_t c = 0; c < v.size(); ++c) {
            last_[c] = v[c];
            if (std::isfinite(v[c]) && !(std::fabs(v[c]) <= largest_[c])) largest_[c] = std::fabs(v[c]);
        }
        return v;
    }

    std::vector<double> summary() const override {
        std::vector<double> out;
        for (std::size_t c = 0; c < last_.size(); ++c) {
            out.push_back(last_[c]);
            out.push_back(largest_[c]);
        }
        return out;
    }

private:
    std::function<std::vector<double>(const SnapshotData&)> evaluate_;
    std::vector<double> last_, largest_;
};

}  // namespace

std::vector<std::string> pointwise_summary_columns(const std::vector<std::string>& sample_columns) {
    std::vector<std::string> out;
    for (const auto& c : sample_columns) {
        out.push_back(c + "_final");
        out.push_back(c + "_max");
    }
    return out;
}

std::unique_ptr<ValidationMetric> make_pointwise_metric(
    std::size_t columns, std::function<std::vector<double>(const SnapshotData&)> evaluate) {
    return std::make_unique<PointwiseMetric>(columns, std::move(evaluate));
}

}  // namespace sph
