// sphbench run SPEC: expands an experiment spec and runs it, writing results/<name>/runs.csv
// and what the spec records; or shows the plan (--dry-run), or a short pass for Nsight
// Systems (--profile). An experiment whose spec, binary and options are unchanged is skipped.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "case_file.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "experiment_preamble.hpp"
#include "experiment_runner.hpp"
#include "statistics.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
    ExperimentArgs experiment;  // spec, --set, --scale, --backend, --out, --only, --force
    std::string float64_binary;
    bool dry_run = false, profile = false, quiet = false;
};

constexpr long profile_steps = 20;
constexpr double cuda_rate = 1e8;           // particle-steps per second, rough
constexpr double host_rate_per_core = 1e6;  // particle-steps per second per core, rough

// Particles of a run, boundary included, without building a large scene: a `particles`
// option is the fluid count, so a small version of the scene is built and its boundary,
// a surface, scaled by the 2/3 power of the fluid ratio.
std::size_t particle_estimate(const PlannedRun& run, std::map<std::string, std::size_t>& cache) {
    constexpr double probe_fluid = 20000;
    SettingMap options = run.scene_options;
    double fluid = 0;
    if (auto it = options.find("particles"); it != options.end()) {
        fluid = std::stod(it->second);
        if (fluid > probe_fluid) it->second = std::to_string(long(probe_fluid));
    }
    std::string key = run.scene;
    for (const auto& [k, v] : options) key += " " + k + "=" + v;
    auto found = cache.find(key);
    if (found == cache.end()) {
        const Scene probe = build_scene(run.scene, options);
        if (fluid <= 0 || double(probe.fluid_count()) >= fluid) {
            found = cache.emplace(key, probe.size()).first;
        } else {
            const double boundary = double(probe.n_boundary) * std::pow(fluid / double(probe.fluid_count()), 2.0 / 3.0);
            found = cache.emplace(key, std::size_t(fluid + boundary)).first;
        }
    }
    return found->second;
}

void print_plan(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs) {
    std::printf("%s: %s\n%zu runs from %s\n", spec.name.c_str(), spec.reproduces.c_str(), runs.size(),
                spec.path.c_str());
    std::printf("%-40s %-14s %6s %6s %8s  %-30s %s\n", "run_id", "scene", "steps", "warmup", "end_time", "scene options",
                "solver (non-default)");
    double cuda_work = 0, host_work = 0;
    std::size_t uncapped = 0;  // runs to an end time without a step cap: their steps are not known ahead
    std::map<std::string, std::size_t> estimates;
    for (const auto& r : runs) {
        std::string opts, solver = r.solver.backend == BackendKind::cuda ? "cuda" : "host";
        for (const auto& [k, v] : r.scene_options) opts += (opts.empty() ? "" : " ") + k + "=" + v;
        static const SettingMap defaults = complete_solver_settings({});
        for (const auto& [k, v] : r.solver_settings)  // only what differs from the defaults
            if (k != "backend" && defaults.at(k) != v) solver += " " + k + "=" + v;
        const std::string steps = r.steps > 0 ? std::to_string(r.steps) : "-";
        const std::string end = r.end_time > 0 ? format_number(r.end_time) + " s" : "-";
        std::printf("%-40s %-14s %6s %6ld %8s  %-30s %s\n", r.run_id.c_str(), r.scene.c_str(), steps.c_str(), r.warmup,
                    end.c_str(), opts.empty() ? "(defaults)" : opts.c_str(), solver.c_str());
        if (r.steps == 0) {
            ++uncapped;
            continue;
        }
        const double work = double(particle_estimate(r, estimates)) * double(r.steps + r.warmup);
        (r.solver.backend == BackendKind::cuda ? cuda_work : host_work) += work;
    }
    const int cores = std::max(1, int(std::thread::hardware_concurrency()));
    const double seconds = cuda_work / cuda_rate + host_work / (host_rate_per_core * cores);
    std::printf("cost: %.3g particle-steps (boundary included); about %.0f s (rough rates: %.0e particle-steps/s on CUDA, %.0e per core "
                "on the host, %d cores)\n",
                cuda_work + host_work, seconds, cuda_rate, host_rate_per_core, cores);
    if (uncapped > 0)
        std::printf("(%zu run(s) to an end time without a step cap are not in the estimate: their step counts are "
                    "known only as they run)\n",
                    uncapped);
}

void profile_pass(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs, const RunArgs& a,
                  const CommandContext& ctx) {
    std::string cmd;
    for (int i = 0; i < ctx.argc; ++i) cmd += (i ? " " : "") + std::string(ctx.argv[i]);
    std::printf("profile pass: up to %ld steps per run, no phase timers, nothing written. For a timeline, run it under Nsight Systems:\n"
                "  nsys profile --trace=cuda,nvtx,osrt --output=%s/%s-profile %s\n",
                profile_steps, a.experiment.out.c_str(), spec.name.c_str(), cmd.c_str());
    for (const auto& run : runs) {
        SceneRunRequest req = scene_request(spec, run);
        req.steps = run.steps > 0 ? std::min(run.steps, profile_steps) : profile_steps;
        req.warmup = 0;
        req.end_time = 0;  // a short pass of steps, whatever the run's end time
        req.snapshot_every = 0;
        req.out_dir.clear();
        req.progress = !a.quiet;
        req.solver.timing = false;  // no CUDA events in a pass meant for Nsight
        const SceneRunResult r = run_scene(req);
        // Untimed pass: the wall clock over the whole run (scene building excluded) is all there is.
        std::printf("%s: %zu particles, %ld steps, %.3f ms per step by wall clock\n", run.run_id.c_str(), r.particles,
                    req.steps, 1e3 * r.wall_seconds / double(std::max(1L, req.steps)));
    }
}

void run_spec(const RunArgs& a, CommandContext& ctx) {
    const Experiment e = load_experiment(a.experiment, ExperimentKind::runs);
    const ExperimentSpec& spec = e.spec;
    const std::vector<PlannedRun>& runs = e.runs;
    const PlannedRun& first = runs.front();
    const bool host_reduced = e.reduced && first.solver.backend == BackendKind::host && spec.host;
    if (host_reduced) {
        std::string what = "particles x" + format_number(first.scale);
        if (spec.host->steps > 0 && first.steps != spec.steps)
            what += ", " + std::to_string(spec.host->steps) + " steps" +
                    (spec.steps > 0 ? " instead of " + std::to_string(spec.steps) : std::string());
        if (spec.host->end_time > 0) what += ", end time " + format_number(spec.host->end_time) + " s";
        std::printf("%s: no GPU run: reduced scale on the host backend (%s)\n", spec.name.c_str(), what.c_str());
    }
    if (a.dry_run) {
        print_plan(spec, runs);
        ctx.exit_code = exit_ok;
        return;
    }
    // After --dry-run, which shows every run whichever build it needs.
    DelegatedRuns delegated = plan_delegation(runs, a.float64_binary);
    for (const auto& arg : override_arguments(a.experiment)) delegated.arguments.push_back(arg);
    if (a.profile) {
        profile_pass(spec, runs, a, ctx);
        ctx.exit_code = exit_ok;
        return;
    }

    ExperimentRunOptions opt;
    opt.out_dir = a.experiment.out;
    opt.quiet = a.quiet;
    opt.metadata = experiment_metadata(e, a.experiment, ctx);
    if (!delegated.run_ids.empty()) {
        opt.metadata.emplace_back("float64_binary", delegated.binary);
        opt.metadata.emplace_back("float64_binary_hash", binary_hash(delegated.binary));
    }
    opt.delegated = delegated;

    const std::string runs_csv = (fs::path(e.dir) / "runs.csv").string();
    if (skip_up_to_date(e, a.experiment, runs_csv, opt.metadata)) {
        ctx.exit_code = exit_ok;
        return;
    }
    const ExperimentOutcome out = run_experiment(spec, runs, opt);
    if (!a.quiet)
        for (const auto& f : out.files) std::printf("wrote %s\n", f.c_str());
    else
        std::printf("%s: %zu runs, wrote %s\n", spec.name.c_str(), runs.size(), out.runs_csv.c_str());
    ctx.exit_code = exit_ok;
}

}  // namespace

void add_run_command(CLI::App& app, CommandContext& ctx) {
    auto a = std::make_shared<RunArgs>();
    CLI::App* cmd = app.add_subcommand(
        "run", "run an experiment spec (experiments/*.toml): every run, its timings and counters, into "
               "DIR/<name>/runs.csv with full provenance; skipped when spec, binary and options are unchanged");
    cmd->add_option("spec", a->experiment.spec, "experiment spec, e.g. experiments/fig4.toml")->required();
    std::string solver_keys;
    for (const auto& k : solver_setting_keys()) solver_keys += (solver_keys.empty() ? "" : ", ") + k;
    cmd->add_option("--set", a->experiment.settings,
                    "override key=value in every run (repeatable): a solver key (" + solver_keys +
                        "), set.<scene option>, steps, end_time, warmup or repetitions");
    add_end_time_option(*cmd, a->experiment, std::string(run_setting("end_time").help) + ", in every run");
    cmd->add_option("--scale", a->experiment.scale, "multiply every particle count by F (dp by F^(-1/3))")
        ->check(in_range(number_above(0)));
    cmd->add_option("--backend", a->experiment.backend, "cuda, host or auto (default: the spec's, else auto)")
        ->check(setting_validator("backend"));
    cmd->add_option("--out", a->experiment.out, "results folder; the experiment writes into DIR/<name>/")->capture_default_str();
    cmd->add_option("--only", a->experiment.only, "run only this run id (repeatable); the table then holds only these");
    cmd->add_option("--float64-binary", a->float64_binary,
                    "a float64 build of sphbench (-DSPH_DOUBLE=ON) to run the runs with precision = \"float64\"");
    cmd->add_flag("--dry-run", a->dry_run, "print the expanded runs and their estimated cost; run nothing");
    cmd->add_flag("--profile", a->profile,
                  "run a short pass of each run (20 steps, nothing written) to record under Nsight Systems");
    cmd->add_flag("--force", a->experiment.force, "run even when the results are up to date");
    cmd->add_flag("--quiet", a->quiet, "no progress line and no per-run lines");
    cmd->callback([a, &ctx] { run_spec(*a, ctx); });
}

}  // namespace sph
