// sphbench run SPEC: expands an experiment spec and runs it, writing results/<name>/runs.csv
// and what the spec records; or shows the plan (--dry-run), or a short pass for Nsight
// Systems (--profile). An experiment whose spec, binary and options are unchanged is skipped.
// With --baseline, its results are then compared with a baseline's, and configurations whose
// verdict is AMBIGUOUS get more repetitions until it is known or max_repetitions is reached.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "case_file.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "comparison_report.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "experiment_preamble.hpp"
#include "experiment_runner.hpp"
#include "regression_compare.hpp"
#include "repetition_plan.hpp"
#include "statistics.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
    ExperimentArgs experiment;  // spec, --set, --scale, --backend, --out, --only, --force
    std::string float64_binary;
    std::string baseline, max_repetitions;  // --baseline DIR, --max-repetitions N (checked as the spec key)
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

// The baseline's results: DIR itself (a result folder, runs.csv or benchmark JSON), or
// DIR/<name> when DIR is a results root such as --out.
std::string baseline_results(const std::string& dir, const std::string& name) {
    const fs::path nested = fs::path(dir) / name;
    if (fs::is_directory(dir) && !fs::exists(fs::path(dir) / "runs.csv") && fs::exists(nested / "runs.csv"))
        return nested.string();
    return dir;
}

// The baseline of --baseline and the cap on repetitions.
struct Baseline {
    std::string path;
    ResultSet results;
    long max_repetitions = 0;
};

// Read and checked before anything runs, so that bad input costs no run.
Baseline load_baseline(const Experiment& e, const RunArgs& a, const DelegatedRuns& delegated) {
    if (!delegated.run_ids.empty())
        throw InputError("--baseline adds repetitions only to runs of this build's precision; " + e.spec.path +
                         " has runs for --float64-binary");
    Baseline b;
    b.max_repetitions = a.max_repetitions.empty()
                            ? e.spec.max_repetitions
                            : check_run_value("max_repetitions", a.max_repetitions, "--max-repetitions");
    b.path = baseline_results(a.baseline, e.spec.name);
    b.results = load_results(b.path);
    return b;
}

// --baseline: compare the experiment's results with the baseline's; while a configuration has
// an AMBIGUOUS verdict, run as many repetitions of it again as it has (up to max_repetitions)
// and compare again, as nvbench runs until its noise criterion is met. NOISY configurations
// get none: more repetitions on a disturbed machine do not settle them. The exit code is
// compare's: 0, 1 a regression, 4 still inconclusive.
int settle_against_baseline(const Experiment& e, const Baseline& b, const ExperimentRunOptions& opt) {
    const long cap = b.max_repetitions;
    const std::string& baseline_path = b.path;
    const ResultSet& baseline = b.results;
    const CompareOptions options;  // compare's defaults
    std::vector<PlannedRun> runs = e.runs;
    for (;;) {
        const std::string runs_csv = (fs::path(e.dir) / "runs.csv").string();
        const Comparison c = compare_results(baseline, load_results(e.dir), options);
        if (!c.comparable())
            throw InputError("--baseline '" + baseline_path + "' has no run and metric of '" + e.spec.name +
                             "' to compare with (runs are matched by their config)");
        // Repetitions so far, from the table itself: an earlier --baseline may have added some.
        const CsvTable table = read_csv(runs_csv);
        std::map<std::string, long> have;
        for (std::size_t i = 0; i < table.rows.size(); ++i) {
            const std::string& rep = table.cell(i, "repetition");
            long& n = have[table.cell(i, "config")];
            n = std::max(n, rep.empty() ? 1L : std::stol(rep));
        }
        const RepetitionPlan plan = more_repetitions(c, runs, have, cap);
        const std::vector<PlannedRun>& more = plan.runs;
        if (more.empty()) {
            print_comparison(c, options, baseline_path, e.dir);
            for (const auto& config : plan.capped)
                std::printf("%s: still AMBIGUOUS after %ld repetitions (max_repetitions; --max-repetitions N for more)\n",
                            config.c_str(), have[config]);
            return comparison_exit_code(c);
        }
        std::set<std::string> growing;
        for (const auto& p : more) growing.insert(p.config);
        std::printf("%s: inconclusive against %s: %zu more repetition(s) of %zu configuration(s), up to %ld each\n",
                    e.spec.name.c_str(), baseline_path.c_str(), more.size(), growing.size(), cap);
        std::fflush(stdout);
        append_runs(e.spec, runs, more, opt);
        runs.insert(runs.end(), more.begin(), more.end());
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
    const std::optional<Baseline> baseline =
        a.baseline.empty() ? std::nullopt : std::optional<Baseline>(load_baseline(e, a, delegated));

    const std::string runs_csv = (fs::path(e.dir) / "runs.csv").string();
    if (!skip_up_to_date(e, a.experiment, runs_csv, opt.metadata)) {
        const ExperimentOutcome out = run_experiment(spec, runs, opt);
        if (!a.quiet)
            for (const auto& f : out.files) std::printf("wrote %s\n", f.c_str());
        else
            std::printf("%s: %zu runs, wrote %s\n", spec.name.c_str(), runs.size(), out.runs_csv.c_str());
    }
    ctx.exit_code = baseline ? settle_against_baseline(e, *baseline, opt) : exit_ok;
}

}  // namespace

void add_run_command(CLI::App& app, CommandContext& ctx) {
    auto a = std::make_shared<RunArgs>();
    CLI::App* cmd = app.add_subcommand(
        "run", "run an experiment spec (experiments/*.toml): every run, its timings and counters, into "
               "DIR/<name>/runs.csv with full provenance; skipped when spec, binary and options are unchanged.\nExit "
               "codes: 0 done, 2 bad input, 3 a failed run; with --baseline also those of `compare`: 1 a regression, "
               "4 still inconclusive after max_repetitions (AMBIGUOUS) or NOISY (a disturbed machine: rerun on a "
               "quiet one)");
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
    cmd->add_option("--baseline", a->baseline,
                    "after running, compare with this result folder (or DIR/<name>) as `compare` does; while a "
                    "configuration's verdict is AMBIGUOUS, run more repetitions of it (doubling, up to max_repetitions)");
    cmd->add_option("--max-repetitions", a->max_repetitions,
                    "most repetitions of a configuration that --baseline runs (default: the spec's max_repetitions, "
                    "else 16)");
    cmd->add_flag("--dry-run", a->dry_run, "print the expanded runs and their estimated cost; run nothing");
    cmd->add_flag("--profile", a->profile,
                  "run a short pass of each run (20 steps, nothing written) to record under Nsight Systems");
    cmd->add_flag("--force", a->experiment.force, "run even when the results are up to date");
    cmd->add_flag("--quiet", a->quiet, "no progress line and no per-run lines");
    cmd->callback([a, &ctx] { run_spec(*a, ctx); });
}

}  // namespace sph
