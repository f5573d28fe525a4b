#pragma once
// Samples the gauges (solver/gauge.hpp) every `every` simulated seconds of each, on the
// device, and writes <run>_gauges.csv when the run ends: time, then each gauge's columns;
// a row is written whenever any gauge is due (the state before the first step included),
// with the cells of gauges not due then left empty. Under MPI every rank samples (the sums
// are gathered); the rank given a path writes.
#include <string>
#include <vector>

#include "provenance.hpp"
#include "step_sink.hpp"

namespace sph {

class GaugeSink final : public StepSink {
public:
    GaugeSink(std::vector<Gauge> gauges, std::string path, Metadata metadata)
        : gauges_(std::move(gauges)), path_(std::move(path)), metadata_(std::move(metadata)) {}
    void begin(Simulation& sim) override;
    void after_step(Simulation& sim, const StepRecord&, const StepPoint&) override { sample(sim); }
    void end(Simulation&) override;
    const std::string& path() const { return path_; }
    std::vector<std::string> columns() const;
    const std::vector<std::vector<std::string>>& rows() const { return rows_; }

private:
    void sample(Simulation& sim);

    std::vector<Gauge> gauges_;
    std::string path_;
    Metadata metadata_;
    std::vector<double> next_;  // each gauge's next sample time
    std::vector<std::vector<std::string>> rows_;
};

}  // namespace sph
