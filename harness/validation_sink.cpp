#include "validation_sink.hpp"

#include <chrono>

namespace sph {

void ValidationSink::after_step(Simulation& sim, const StepRecord& r, const StepPoint& at) {
    if (!at.last && !recorder_.due(r.time)) return;
    const auto t0 = std::chrono::steady_clock::now();
    recorder_.sample(sim.snapshot());
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void ValidationSink::end(Simulation&) {
    summary_ = recorder_.summary();
    if (!path_.empty()) written_ = recorder_.write_csv(path_, metadata_);
}

}  // namespace sph
