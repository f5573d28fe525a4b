#pragma once
// HDF5 snapshots (with an XDMF index) of the start and of every `every`-th step, warm-up
// included. A snapshot gathers every rank's particles, so under MPI every rank takes it and
// only the writing rank (a non-empty directory) writes it.
#include <memory>
#include <string>
#include <vector>

#include "io/snapshot_writer.hpp"
#include "step_sink.hpp"

namespace sph {

class SnapshotSink final : public StepSink {
public:
    // directory "": take the snapshots (a collective) but write nothing.
    SnapshotSink(long every, const std::string& directory, const std::string& basename);
    void begin(Simulation& sim) override { take(sim); }
    void after_step(Simulation& sim, const StepRecord&, const StepPoint& at) override {
        if (at.step % every_ == 0) take(sim);
    }
    // The snapshots written and their index; empty on a rank that does not write.
    std::vector<std::string> files() const;

private:
    void take(Simulation& sim);
    long every_;
    std::unique_ptr<SnapshotSeries> series_;
};

}  // namespace sph
