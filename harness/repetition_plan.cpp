#include "repetition_plan.hpp"

#include <algorithm>
#include <set>

namespace sph {

RepetitionPlan more_repetitions(const Comparison& c, const std::vector<PlannedRun>& planned,
                                const std::map<std::string, long>& have, long cap) {
    std::set<std::string> ambiguous, noisy;
    for (const auto& r : c.rows) {
        if (r.verdict == Verdict::ambiguous) ambiguous.insert(r.run);
        if (r.verdict == Verdict::noisy) noisy.insert(r.run);
    }
    RepetitionPlan plan;
    for (const auto& config : ambiguous) {
        const auto model =
            std::find_if(planned.begin(), planned.end(), [&](const PlannedRun& r) { return r.config == config; });
        if (noisy.count(config) || model == planned.end()) continue;
        const auto found = have.find(config);
        const long n = found == have.end() ? 1 : found->second, next = std::min(cap, 2 * n);
        if (next <= n) plan.capped.push_back(config);
        for (long rep = n + 1; rep <= next; ++rep) {
            PlannedRun p = *model;
            p.repetition = rep;
            p.run_id = config + "_rep" + std::to_string(rep);
            plan.runs.push_back(std::move(p));
        }
    }
    return plan;
}

}  // namespace sph
