#pragma once
// The blow-up policy of studies (spec `blow_up = "record"`, the stability probes): a blow-up
// ends the run as a result, recorded in the loop's outcome, instead of failing it. Without
// this rule a run loop fails on a blow-up.
#include "stop_rule.hpp"

namespace sph {

class RecordBlowUp final : public StopRule {
public:
    bool reached(const Simulation&) override { return false; }
    bool ends_on_blow_up() const override { return true; }
};

}  // namespace sph
