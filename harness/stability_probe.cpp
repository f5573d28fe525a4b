#include "stability_probe.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "progress.hpp"

namespace sph {

TrialOutcome run_trial(const Scene& scene, const SolverOptions& solver, const TrialTarget& target, long sample_every,
                       std::vector<EnergySample>* samples) {
    TrialOutcome out;
    out.cfl = solver.cfl > 0 ? solver.cfl : scene.cfl;
    const auto t0 = std::chrono::steady_clock::now();
    Simulation sim(scene, solver);
    auto sample = [&] {
        if (samples) samples->push_back(measure_energy(sim.snapshot(), scene.params, scene.dp));
    };
    if (sample_every > 0) sample();
    char label[64];
    std::snprintf(label, sizeof label, "%s cfl %.4g", scene.name.c_str(), out.cfl);
    Progress progress(label, target.max_steps, target.progress);
    auto done = [&] { return target.time > 0 ? sim.time() >= target.time : sim.steps_taken() >= target.max_steps; };
    try {
        while (!done()) {
            if (sim.steps_taken() >= target.max_steps) {
                progress.finish();
                throw InputError("scene '" + scene.name + "' at cfl " + std::to_string(out.cfl) + " reached only t = " +
                                 std::to_string(sim.time()) + " s of " + std::to_string(target.time) + " s in " +
                                 std::to_string(target.max_steps) + " steps; raise 'steps' or lower 'time'");
            }
            sim.step();
            if (sample_every > 0 && (sim.steps_taken() % sample_every == 0 || done())) sample();
            if (sim.steps_taken() % 50 == 0) progress.update(sim.steps_taken());
        }
        out.stable = true;
    } catch (const BlowUpError& e) {
        out.stable = false;
        out.failed_step = e.step;
        out.particle = e.particle;
        out.quantity = e.quantity;
        out.message = e.what();
        out.last_good = e.last_good;
    }
    progress.finish();
    out.steps = sim.steps_taken();
    out.time = sim.time();
    out.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

CflLimit find_cfl_limit(const Scene& scene, SolverOptions solver, const TrialTarget& target, double low, double high,
                        long bisections) {
    CflLimit r;
    auto trial = [&](double cfl) {
        solver.cfl = cfl;
        r.trials.push_back(run_trial(scene, solver, target));
        r.trials.back().last_good.reset();  // the study tabulates failures; it keeps no states
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
