#pragma once
// What `run --baseline` runs next: after a comparison with the baseline, the configurations
// with an AMBIGUOUS row (and no NOISY one) get as many repetitions again as they have, up to
// the cap, as nvbench keeps sampling until its noise criterion is met. NOISY configurations get
// none: more repetitions on a disturbed machine do not settle them.
#include <map>
#include <string>
#include <vector>

#include "experiment_spec.hpp"
#include "regression_compare.hpp"

namespace sph {

struct RepetitionPlan {
    std::vector<PlannedRun> runs;      // the repetitions to add: <config>_rep<k>, k after those there are
    std::vector<std::string> capped;   // AMBIGUOUS configurations that already have `cap` repetitions
};

// `planned`: the experiment's runs (one of each configuration is the model of its new ones);
// `have`: the repetitions each configuration has in runs.csv.
RepetitionPlan more_repetitions(const Comparison& c, const std::vector<PlannedRun>& planned,
                                const std::map<std::string, long>& have, long cap);

}  // namespace sph
