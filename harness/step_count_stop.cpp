#include "step_count_stop.hpp"

#include "core/error.hpp"

namespace sph {

bool StepCountStop::reached(const Simulation& sim) {
    if (sim.steps_taken() < steps_) return false;
    if (refusal_) throw InputError(refusal_(sim));
    return true;
}

}  // namespace sph
