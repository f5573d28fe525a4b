#pragma once
// Stops a run after a number of steps (warm-up included). As a cap behind another rule
// (EndTimeStop) it may refuse instead: reaching it then means the target was out of reach,
// an input error worded by `refusal`.
#include <functional>
#include <string>

#include "stop_rule.hpp"

namespace sph {

class StepCountStop final : public StopRule {
public:
    using Refusal = std::function<std::string(const Simulation&)>;
    explicit StepCountStop(long steps, Refusal refusal = {}) : steps_(steps), refusal_(std::move(refusal)) {}
    bool reached(const Simulation& sim) override;
    long steps() const { return steps_; }

private:
    long steps_;
    Refusal refusal_;
};

}  // namespace sph
