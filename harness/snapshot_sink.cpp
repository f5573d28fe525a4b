#include "snapshot_sink.hpp"

namespace sph {

SnapshotSink::SnapshotSink(long every, const std::string& directory, const std::string& basename) : every_(every) {
    if (!directory.empty()) series_ = std::make_unique<SnapshotSeries>(directory, basename);
}

void SnapshotSink::take(Simulation& sim) {
    const SnapshotData s = sim.snapshot();
    if (series_) series_->write(s);
}

std::vector<std::string> SnapshotSink::files() const {
    if (!series_) return {};
    std::vector<std::string> out = series_->files();
    out.push_back(series_->xdmf_path());
    return out;
}

}  // namespace sph
