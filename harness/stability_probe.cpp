#include "stability_probe.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "end_time_stop.hpp"
#include "energy_sink.hpp"
#include "progress_sink.hpp"
#include "record_blow_up.hpp"
#include "run_loop.hpp"
#include "step_count_stop.hpp"

namespace sph {

TrialOutcome run_trial(const Scene& scene, const SolverOptions& solver, const TrialTarget& target,
                       const std::vector<StepSink*>& sinks) {
    TrialOutcome out;
    out.cfl = solver.cfl > 0 ? solver.cfl : scene.cfl;
    const auto t0 = std::chrono::steady_clock::now();
    Simulation sim(scene, solver);
    RunLoop loop(sim);
    // A fixed simulated time, with the step budget as a cap that refuses; or the budget alone.
    std::optional<EndTimeStop> end_time;
    StepCountStop::Refusal refusal;
    if (target.time > 0) {
        loop.stop_when(end_time.emplace(target.time));
        refusal = [&](const Simulation& s) {
            return "scene '" + scene.name + "' at cfl " + std::to_string(out.cfl) + " reached only t = " +
                   std::to_string(s.time()) + " s of " + std::to_string(target.time) + " s in " +
                   std::to_string(target.max_steps) + " steps; raise 'steps' or lower 'time'";
        };
    }
    std::optional<StepCountStop> budget;  // none: a time target without a cap
    if (target.max_steps > 0 || target.time <= 0) loop.stop_when(budget.emplace(target.max_steps, refusal));
    RecordBlowUp blow_up;  // a trial that blows up is the study's answer, not a failure
    loop.stop_when(blow_up);
    for (StepSink* s : sinks) loop.feed(*s);
    char label[64];
    std::snprintf(label, sizeof label, "%s cfl %.4g", scene.name.c_str(), out.cfl);
    ProgressSink progress(label, target.max_steps, target.time, target.progress, 50, false);
    loop.feed(progress);

    const RunLoopOutcome r = loop.run();
    out.stable = !r.blow_up;
    if (r.blow_up) {
        out.failed_step = r.blow_up->step;
        out.particle = r.blow_up->particle;
        out.quantity = r.blow_up->quantity;
        out.message = r.blow_up->message;
    }
    out.steps = r.steps;
    out.time = r.time;
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

TrialOutcome run_trial(const Scene& scene, const SolverOptions& solver, const TrialTarget& target, long sample_every,
                       std::vector<EnergySample>* samples) {
    std::optional<EnergySink> energy;
    std::vector<StepSink*> sinks;
    if (sample_every > 0 && samples) sinks.push_back(&energy.emplace(scene, sample_every, *samples));
    return run_trial(scene, solver, target, sinks);
}

CflLimit find_cfl_limit(const Scene& scene, SolverOptions solver, const TrialTarget& target, double low, double high,
                        long bisections) {
    CflLimit r;
    auto trial = [&](double cfl) {
        solver.cfl = cfl;
        r.trials.push_back(run_trial(scene, solver, target));  // the study tabulates failures; it keeps no states
        return r.trials.back().stable;
    };
    if (trial(high)) {
        r.stable = high;
        return r;
    }
    r.unstable = high;
    if (!trial(low)) {
        r.unstable = low;
        return r;
    }
    r.stable = low;
    for (long k = 0; k < bisections; ++k) {
        const double mid = std::sqrt(r.stable * r.unstable);
        (trial(mid) ? r.stable : r.unstable) = mid;
    }
    return r;
}

}  // namespace sph
