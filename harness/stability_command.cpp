// sphbench stability SPEC: runs a stability study (an experiment spec with a [stability]
// table) and writes its tables with the harness's provenance:
//   probe "cfl-limit": <out>/<name>/summary.csv, one row per run with the largest stable and
//                      smallest unstable CFL number, and trials.csv with every trial;
//   probe "energy":    <out>/<name>/summary.csv, one row per run with the drift of the energy
//                      and of the free surface, and <run_id>_energy.csv with the time series.
// A run that blows up in an energy study is a result (its row says where and why), and its
// last good state is written as <run_id>_last_good (HDF5 + XDMF).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "case_file.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "energy_sink.hpp"
#include "experiment_preamble.hpp"
#include "experiment_runner.hpp"
#include "io/csv_writer.hpp"
#include "last_good_sink.hpp"
#include "stability_probe.hpp"
#include "stability_tables.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

struct StabilityArgs {
    ExperimentArgs experiment;  // spec, --set, --scale, --backend, --out, --force
    bool quiet = false;
};

std::string f(double v) { return CsvWriter::fmt(v); }

void cfl_limit_study(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs, const Metadata& meta,
                     const std::string& dir, bool quiet) {
    const StabilityStudy& st = *spec.stability;
    CsvWriter trials((fs::path(dir) / "trials.csv").string(), trial_table().names(), meta);
    CsvWriter summary((fs::path(dir) / "summary.csv").string(), cfl_limit_table().names(), meta);
    for (const PlannedRun& run : runs) {
        const Scene scene = build_scene(run.scene, run.scene_options);
        const double time = run.end_time > 0 ? run.end_time : st.time;  // end_time, else [stability] time
        const TrialTarget target{time, run.steps, !quiet};
        const CflLimit lim = find_cfl_limit(scene, run.solver, target, st.cfl_low, st.cfl_high, st.bisections);
        double wall = 0;
        const TrialOutcome* smallest_failure = nullptr;
        for (const TrialOutcome& t : lim.trials) {
            wall += t.wall_s;
            trials.row(trial_table().cells(TrialRow{run.run_id, t}));
            if (!t.stable && (!smallest_failure || t.cfl < smallest_failure->cfl)) smallest_failure = &t;
        }
        summary.row(cfl_limit_table().cells(CflLimitRow{StudyRun{run, scene, time}, lim, smallest_failure, wall}));
        std::printf("%s: %zu particles, largest stable cfl %.4g, smallest unstable %.4g (%s at step %ld), %zu trials, "
                    "%.1f s\n",
                    run.run_id.c_str(), scene.size(), lim.stable, lim.unstable,
                    smallest_failure ? smallest_failure->quantity.c_str() : "-",
                    smallest_failure ? smallest_failure->failed_step : 0L, lim.trials.size(), wall);
    }
    trials.commit();
    summary.commit();
}

void energy_study(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs, const Metadata& meta,
                  const std::string& dir, bool quiet) {
    const StabilityStudy& st = *spec.stability;
    CsvWriter summary((fs::path(dir) / "summary.csv").string(), energy_summary_table().names(), meta);
    for (const PlannedRun& run : runs) {
        const Scene scene = build_scene(run.scene, run.scene_options);
        std::vector<EnergySample> samples;
        std::optional<EnergySink> energy;
        LastGoodSink last_good_state(dir, run.run_id);
        std::vector<StepSink*> sinks;
        if (st.sample_every > 0) sinks.push_back(&energy.emplace(scene, st.sample_every, samples));
        sinks.push_back(&last_good_state);
        const double time = run.end_time > 0 ? run.end_time : st.time;  // end_time, else [stability] time
        const TrialOutcome t = run_trial(scene, run.solver, TrialTarget{time, run.steps, !quiet}, sinks);
        // Drifts relative to the energy the water can spend: its initial kinetic energy plus its
        // potential energy above its lowest point (the floor for still water), which does not
        // depend on where the world's origin is.
        const EnergySample& e0 = samples.front();
        const double scale = energy_scale(e0, scene);
        const std::string series = run.run_id + "_energy.csv";
        Metadata m = meta;
        m.emplace_back("run_id", run.run_id);
        m.emplace_back("energy_scale", f(scale));
        CsvWriter csv((fs::path(dir) / series).string(), energy_series_table().names(), m);
        double worst_total = 0, worst_surface = 0;
        for (const EnergySample& e : samples) {
            const double drift = (e.total() - e0.total()) / scale, surface = e.free_surface - e0.free_surface;
            worst_total = std::fabs(drift) > std::fabs(worst_total) ? drift : worst_total;
            worst_surface = std::fabs(surface) > std::fabs(worst_surface) ? surface : worst_surface;
            csv.row(energy_series_table().cells(EnergySampleRow{e, e0, scale}));
        }
        csv.commit();
        const std::string last_good =
            last_good_state.xdmf_path().empty() ? "" : fs::path(last_good_state.xdmf_path()).filename().string();
        const EnergySample& e1 = samples.back();
        summary.row(energy_summary_table().cells(
            EnergySummaryRow{StudyRun{run, scene, time}, t, scale, e0, e1, worst_total, worst_surface, series, last_good}));
        std::printf("%s: %zu particles, %s after %ld steps (t = %.4g s), energy drift %.3g of its scale, free surface "
                    "%+.3g m, %.1f s\n",
                    run.run_id.c_str(), scene.size(), t.stable ? "stable" : ("BLEW UP (" + t.message + ")").c_str(),
                    t.steps, t.time, (e1.total() - e0.total()) / scale, e1.free_surface - e0.free_surface, t.wall_s);
    }
    summary.commit();
}

void run_study(const StabilityArgs& a, CommandContext& ctx) {
    const Experiment e = load_experiment(a.experiment, ExperimentKind::stability);
    const ExperimentSpec& spec = e.spec;
    const std::vector<PlannedRun>& runs = e.runs;
    const PlannedRun& first = runs.front();
    if (e.reduced && first.solver.backend == BackendKind::host)
        std::printf("%s: no GPU run: reduced scale on the host backend (particles x%g, at most %ld steps instead of %ld)\n",
                    spec.name.c_str(), first.scale, first.steps, spec.steps);

    Metadata meta = experiment_metadata(e, a.experiment, ctx);
    meta.emplace_back("probe", spec.stability->probe);
    meta.emplace_back("criterion", "stable = reaches target_time (or max_steps steps when it is 0) without a blow-up: "
                                   "non-finite acceleration, fluid speed above c0, or fluid density outside [0.5, 2] rho0");

    const std::string summary = (fs::path(e.dir) / "summary.csv").string();
    if (skip_up_to_date(e, a.experiment, summary, meta)) {
        ctx.exit_code = exit_ok;
        return;
    }
    fs::create_directories(e.dir);
    fs::remove(summary);  // only a finished study has one
    if (spec.stability->probe == "cfl-limit") cfl_limit_study(spec, runs, meta, e.dir, a.quiet);
    else energy_study(spec, runs, meta, e.dir, a.quiet);
    std::printf("wrote %s\n", summary.c_str());
    ctx.exit_code = exit_ok;
}

}  // namespace

void add_stability_command(CLI::App& app, CommandContext& ctx) {
    auto a = std::make_shared<StabilityArgs>();
    CLI::App* cmd = app.add_subcommand(
        "stability", "run a stability study (an experiment spec with [stability]): the largest stable CFL number by "
                     "bisection, or the drift of energy and free surface over a long run");
    cmd->add_option("spec", a->experiment.spec, "stability spec, e.g. experiments/stability-cfl.toml")->required();
    cmd->add_option("--set", a->experiment.settings, "override key=value in every run (repeatable), as for `sphbench run`");
    add_end_time_option(*cmd, a->experiment,
                        "the simulated time every trial must reach (replaces end_time and [stability] time); a trial "
                        "that needs more than `steps` steps is refused");
    cmd->add_option("--scale", a->experiment.scale, "multiply every particle count by F (dp by F^(-1/3))")
        ->check(in_range(number_above(0)));
    cmd->add_option("--backend", a->experiment.backend, "cuda, host or auto (default: the spec's, else auto)")
        ->check(setting_validator("backend"));
    cmd->add_option("--out", a->experiment.out, "results folder; the study writes into DIR/<name>/")->capture_default_str();
    cmd->add_flag("--force", a->experiment.force, "run even when the results are up to date");
    cmd->add_flag("--quiet", a->quiet, "no progress line");
    cmd->callback([a, &ctx] { run_study(*a, ctx); });
}

}  // namespace sph
