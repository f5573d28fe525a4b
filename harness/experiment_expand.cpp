// Expansion of a spec into the runs it asks for: runs x sweep points x repetitions, with the
// command line's overrides and the reduced scale of [host] applied.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "core/error.hpp"
#include "experiment_spec.hpp"

namespace sph {
namespace {

long parse_count(const std::string& key, const std::string& text) { return check_run_value(key, text, "--set " + key); }

// Particle counts scale with `scale`; a lattice spacing with its inverse cube root.
void apply_scale(SettingMap& options, double scale) {
    if (scale == 1.0) return;
    if (auto it = options.find("particles"); it != options.end()) {
        char* end = nullptr;
        const double n = std::strtod(it->second.c_str(), &end);
        if (*end != '\0') throw InputError("scene option 'particles' must be a number to be scaled, got '" + it->second + "'");
        it->second = std::to_string(std::max(1LL, std::llround(n * scale)));
    }
    if (auto it = options.find("dp"); it != options.end()) {
        char* end = nullptr;
        const double dp = std::strtod(it->second.c_str(), &end);
        if (*end != '\0') throw InputError("scene option 'dp' must be a number to be scaled, got '" + it->second + "'");
        it->second = format_number(dp / std::cbrt(scale));
    }
}

struct SweepPoint {
    std::vector<std::pair<std::string, std::string>> values;  // key, value
};

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes) {
    std::vector<SweepPoint> points(1);
    for (const auto& axis : axes) {
        std::vector<SweepPoint> next;
        for (const auto& p : points)
            for (const auto& v : axis.values) {
                SweepPoint q = p;
                q.values.emplace_back(axis.key, v);
                next.push_back(std::move(q));
            }
        points = std::move(next);
    }
    return points;
}

std::string short_key(const std::string& key) { return key.rfind("set.", 0) == 0 ? key.substr(4) : key; }

}  // namespace

std::vector<PlannedRun> expand(const ExperimentSpec& spec, const ExpandOptions& options) {
    number_above(0).check("--scale", format_number(options.scale));
    if (!options.backend.empty()) check_solver_value("backend", options.backend, "--backend");

    // Overrides: solver keys, scene options, or the run counts. A swept key that is
    // overridden is no longer swept.
    SettingMap solver_over, scene_over;
    long steps = spec.steps, warmup = spec.warmup, repetitions = spec.repetitions;
    double end_time = spec.end_time;
    bool end_time_overridden = false;
    bool steps_overridden = false;
    std::set<std::string> overridden;
    for (const auto& [key, value] : options.overrides) {
        if (is_solver_setting(key)) solver_over[key] = check_solver_value(key, value, "--set " + key);
        else if (key.rfind("set.", 0) == 0 && key.size() > 4) scene_over[key.substr(4)] = value;
        else if (key == "steps") steps = parse_count(key, value), steps_overridden = true;
        else if (key == "warmup") warmup = parse_count(key, value);
        else if (key == "end_time") end_time = check_run_number(key, value, "--set " + key), end_time_overridden = true;
        else if (key == "repetitions") repetitions = parse_count(key, value);
        else {
            std::string known;
            for (const auto& k : solver_setting_keys()) known += k + ", ";
            throw InputError("--set names an unknown key '" + key + "' (known: " + known +
                             "steps, end_time, warmup, repetitions, set.<scene option>)");
        }
        overridden.insert(key);
    }
    if (!options.backend.empty()) solver_over["backend"] = options.backend, overridden.insert("backend");
    std::vector<SweepAxis> axes;
    for (const auto& axis : spec.sweep)
        if (!overridden.count(axis.key)) axes.push_back(axis);
    const std::vector<SweepPoint> points = sweep_points(axes);

    std::vector<PlannedRun> planned;
    std::set<std::string> ids;
    for (const auto& run : spec.runs) {
        for (const auto& point : points) {
            SettingMap solver = spec.solver, scene = run.scene_options;
            for (const auto& [k, v] : run.solver) solver[k] = v;
            std::string config = run.label;
            for (const auto& [k, v] : point.values) {
                if (k.rfind("set.", 0) == 0) scene[k.substr(4)] = v;
                else solver[k] = v;
                config += "_" + filename_safe(short_key(k) + "-" + v);
            }
            for (const auto& [k, v] : solver_over) solver[k] = v;
            for (const auto& [k, v] : scene_over) scene[k] = v;

            PlannedRun base;
            base.config = config;
            base.label = run.label;
            base.scene = run.scene;
            base.solver_settings = complete_solver_settings(solver);
            base.solver = to_solver_options(base.solver_settings, options.gpu_available);
            // A run's own steps and end time replace the spec's; --set replaces both.
            const long run_steps = run.steps && !steps_overridden ? *run.steps : steps;
            const double run_end_time = run.end_time && !end_time_overridden ? *run.end_time : end_time;
            base.steps = run_steps;
            base.warmup = warmup;
            base.snapshot_every = spec.snapshot_every;
            base.record_blow_up = spec.record_blow_ups;
            if (run.validation) base.validation = *run.validation;
            else if (spec.validation) base.validation = *spec.validation;
            // The run's end time: the spec's or --set's, else its validation's. Validation
            // then records the end time the run has.
            const double asked_end_time = run_end_time > 0 ? run_end_time : base.validation.end_time;
            base.end_time = asked_end_time;
            if (base.validation.enabled()) base.validation.end_time = base.end_time;
            base.scale = options.scale;
            const bool on_host = base.solver.backend == BackendKind::host;
            if (on_host && spec.host) {
                base.scale *= spec.host->scale;
                if (spec.host->steps > 0 && !steps_overridden) base.steps = spec.host->steps;
                if (spec.host->end_time > 0 && !end_time_overridden && base.end_time > 0) {
                    base.end_time = spec.host->end_time;
                    if (base.validation.enabled()) base.validation.end_time = base.end_time;
                }
            }
            base.reduced_scale = base.scale != 1.0 || base.steps != run_steps || base.end_time != asked_end_time;
            if (base.steps == 0 && base.end_time <= 0)
                throw InputError(spec.path + ": run '" + config + "' has neither 'steps' nor 'end_time'; give one");
            apply_scale(scene, base.scale);
            base.scene_options = scene;

            for (long rep = 1; rep <= repetitions; ++rep) {
                PlannedRun p = base;
                p.repetition = rep;
                p.run_id = repetitions > 1 ? config + "_rep" + std::to_string(rep) : config;
                if (!ids.insert(p.run_id).second)
                    throw InputError(spec.path + ": two runs expand to the same id '" + p.run_id +
                                     "'; give them different labels");
                planned.push_back(std::move(p));
            }
        }
    }
    return planned;
}

}  // namespace sph
