#pragma once
// On a blow-up, writes the last good state (the one before the failing update) as
// <dir>/<basename>_last_good (HDF5 + XDMF) and says where.
#include <string>

#include "step_sink.hpp"

namespace sph {

class LastGoodSink final : public StepSink {
public:
    LastGoodSink(std::string directory, std::string basename)
        : directory_(std::move(directory)), basename_(std::move(basename)) {}
    void after_step(Simulation&, const StepRecord&, const StepPoint&) override {}
    void blow_up(const BlowUpError& e, std::string& where) override;
    // The XDMF index written, "" when the run did not blow up.
    const std::string& xdmf_path() const { return xdmf_; }

private:
    std::string directory_, basename_, xdmf_;
};

}  // namespace sph
