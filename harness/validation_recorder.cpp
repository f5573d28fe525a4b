#include "validation_recorder.hpp"

#include <cmath>

#include "core/error.hpp"
#include "io/csv_writer.hpp"

namespace sph {

std::string scenes_with_validation() {
    std::string s;
    for (const auto& m : validation_metrics()) s += (s.empty() ? "" : ", ") + m.scene;
    return s;
}

ValidationRecorder::ValidationRecorder(const Scene& scene, const ValidationRequest& request)
    : info_(find_validation_metric(scene.name)), request_(request) {
    if (!info_)
        throw InputError("scene '" + scene.name + "' has no validation metric (scenes with one: " +
                         scenes_with_validation() + ")");
    metric_ = info_->make(scene);
}

bool ValidationRecorder::due(double time) const {
    // Output times fall between steps: the first state at or past each one is sampled.
    return time >= next_time_ * (1 - 1e-12);
}

void ValidationRecorder::sample(const SnapshotData& state) {
    if (state.time == last_time_) return;  // the end coincided with an output time
    std::vector<double> row = {double(state.step), state.time};
    for (double v : metric_->sample(state)) row.push_back(v);
    rows_.push_back(std::move(row));
    last_time_ = state.time;
    next_time_ = (std::floor(state.time / request_.every * (1 + 1e-12)) + 1) * request_.every;
}

std::vector<std::pair<std::string, double>> ValidationRecorder::summary() const {
    std::vector<std::pair<std::string, double>> out;
    const std::vector<double> values = metric_->summary();
    for (std::size_t i = 0; i < values.size() && i < info_->summary_columns.size(); ++i)
        out.emplace_back(info_->summary_columns[i], values[i]);
    return out;
}

std::string ValidationRecorder::write_csv(const std::string& path, const Metadata& metadata) const {
    std::vector<std::string> columns = {"step", "time"};
    for (const auto& c : info_->sample_columns) columns.push_back(c);
    Metadata meta = metadata;
    meta.emplace_back("validation", info_->description);
    meta.emplace_back("validation_every", CsvWriter::fmt(request_.every));
    meta.emplace_back("validation_end_time", CsvWriter::fmt(request_.end_time));
    for (const auto& [k, v] : summary()) meta.emplace_back(k, CsvWriter::fmt(v));
    CsvWriter csv(path, columns, meta);
    for (const auto& r : rows_) {
        std::vector<std::string> cells = {std::to_string(long(r[0]))};
        for (std::size_t i = 1; i < r.size(); ++i) cells.push_back(CsvWriter::fmt(r[i]));
        csv.row(cells);
    }
    csv.commit();
    return path;
}

}  // namespace sph
