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

#include "cli_options.hpp"
#include "commands.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "experiment_runner.hpp"
#include "result_freshness.hpp"
#include "io/csv_writer.hpp"
#include "stability_probe.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

struct StabilityArgs {
    std::string spec;
    std::vector<std::string> settings;
    double scale = 1.0;
    std::string backend;
    std::string out = "results";
    bool force = false, quiet = false;
};

std::string f(double v) { return CsvWriter::fmt(v); }

// The columns every summary row starts with: what ran, where, at which size.
std::vector<std::string> run_columns() {
    return {"run_id", "scene", "backend", "particles", "fluid", "boundary", "dp", "target_time", "max_steps"};
}
std::vector<std::string> run_cells(const PlannedRun& run, const Scene& s, double time) {
    return {run.run_id,          run.scene,
            run.solver.backend == BackendKind::cuda ? "cuda" : "host",
            std::to_string(s.size()), std::to_string(s.fluid_count()), std::to_string(s.n_boundary), f(s.dp), f(time),
            std::to_string(run.steps)};
}

void cfl_limit_study(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs, const Metadata& meta,
                     const std::string& dir, bool quiet) {
    const StabilityStudy& st = *spec.stability;
    std::vector<std::string> cols = run_columns();
    for (const char* c : {"cfl_stable", "cfl_unstable", "trials", "unstable_failed_step", "unstable_quantity",
                          "unstable_particle", "unstable_message", "wall_s"})
        cols.push_back(c);
    std::vector<std::string> trial_cols = {"run_id", "cfl", "stable", "steps", "time", "failed_step", "particle",
                                           "quantity", "wall_s"};
    CsvWriter trials((fs::path(dir) / "trials.csv").string(), trial_cols, meta);
    CsvWriter summary((fs::path(dir) / "summary.csv").string(), cols, meta);
    for (const PlannedRun& run : runs) {
        const Scene scene = make_scene(run.scene, run.scene_options);
        const TrialTarget target{st.time, run.steps, !quiet};
        const CflLimit lim = find_cfl_limit(scene, run.solver, target, st.cfl_low, st.cfl_high, st.bisections);
        double wall = 0;
        const TrialOutcome* smallest_failure = nullptr;
        for (const TrialOutcome& t : lim.trials) {
            wall += t.wall_s;
            trials.row({run.run_id, f(t.cfl), t.stable ? "true" : "false", std::to_string(t.steps), f(t.time),
                        std::to_string(t.failed_step), t.stable ? "" : std::to_string(t.particle), t.quantity,
                        f(t.wall_s)});
            if (!t.stable && (!smallest_failure || t.cfl < smallest_failure->cfl)) smallest_failure = &t;
        }
        std::vector<std::string> row = run_cells(run, scene, st.time);
        row.push_back(f(lim.stable));
        row.push_back(f(lim.unstable));
        row.push_back(std::to_string(lim.trials.size()));
        row.push_back(smallest_failure ? std::to_string(smallest_failure->failed_step) : "");
        row.push_back(smallest_failure ? smallest_failure->quantity : "");
        row.push_back(smallest_failure ? std::to_string(smallest_failure->particle) : "");
        row.push_back(smallest_failure ? smallest_failure->message : "");
        row.push_back(f(wall));
        summary.row(row);
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
    std::vector<std::string> cols = run_columns();
    for (const char* c : {"cfl", "stable", "steps", "time", "failed_step", "particle", "quantity", "energy_scale",
                          "total_drift", "mechanical_drift", "largest_total_drift", "free_surface_0",
                          "free_surface_drift", "largest_free_surface_drift", "wall_s", "series", "last_good"})
        cols.push_back(c);
    CsvWriter summary((fs::path(dir) / "summary.csv").string(), cols, meta);
    for (const PlannedRun& run : runs) {
        const Scene scene = make_scene(run.scene, run.scene_options);
        std::vector<EnergySample> samples;
        TrialOutcome t = run_trial(scene, run.solver, TrialTarget{st.time, run.steps, !quiet}, st.sample_every, &samples);
        // Drifts relative to the energy the water can spend: its initial kinetic energy plus its
        // potential energy above its lowest point (the floor for still water), which does not
        // depend on where the world's origin is.
        const EnergySample& e0 = samples.front();
        const double scale = energy_scale(e0, scene);
        const std::string series = run.run_id + "_energy.csv";
        Metadata m = meta;
        m.emplace_back("run_id", run.run_id);
        m.emplace_back("energy_scale", f(scale));
        CsvWriter csv((fs::path(dir) / series).string(),
                      {"step", "time", "kinetic", "potential", "internal_fluid", "internal_boundary", "total",
                       "total_drift", "free_surface", "free_surface_drift", "fluid"},
                      m);
        double worst_total = 0, worst_surface = 0;
        for (const EnergySample& e : samples) {
            const double drift = (e.total() - e0.total()) / scale, surface = e.free_surface - e0.free_surface;
            worst_total = std::fabs(drift) > std::fabs(worst_total) ? drift : worst_total;
            worst_surface = std::fabs(surface) > std::fabs(worst_surface) ? surface : worst_surface;
            csv.row({std::to_string(e.step), f(e.time), f(e.kinetic), f(e.potential), f(e.internal_fluid),
                     f(e.internal_boundary), f(e.total()), f(drift), f(e.free_surface), f(surface),
                     std::to_string(e.fluid)});
        }
        csv.commit();
        std::string last_good;
        if (t.last_good) {
            SnapshotSeries s(dir, run.run_id + "_last_good");
            s.write(*t.last_good);
            last_good = fs::path(s.xdmf_path()).filename().string();
        }
        const EnergySample& e1 = samples.back();
        std::vector<std::string> row = run_cells(run, scene, st.time);
        for (const std::string& c :
             {f(t.cfl), std::string(t.stable ? "true" : "false"), std::to_string(t.steps), f(t.time),
              std::to_string(t.failed_step), t.stable ? std::string() : std::to_string(t.particle), t.quantity, f(scale),
              f((e1.total() - e0.total()) / scale), f((e1.mechanical() - e0.mechanical()) / scale), f(worst_total),
              f(e0.free_surface), f(e1.free_surface - e0.free_surface), f(worst_surface), f(t.wall_s), series,
              last_good})
            row.push_back(c);
        summary.row(row);
        std::printf("%s: %zu particles, %s after %ld steps (t = %.4g s), energy drift %.3g of its scale, free surface "
                    "%+.3g m, %.1f s\n",
                    run.run_id.c_str(), scene.size(), t.stable ? "stable" : ("BLEW UP (" + t.message + ")").c_str(),
                    t.steps, t.time, (e1.total() - e0.total()) / scale, e1.free_surface - e0.free_surface, t.wall_s);
    }
    summary.commit();
}

void run_study(const StabilityArgs& a, CommandContext& ctx) {
    const ExperimentSpec spec = load_spec(a.spec);
    check_output_folder("--out", experiment_dir(a.out, spec));
    if (!spec.stability)
        throw InputError("experiment spec '" + spec.path + "' has no [stability] table; run it with `sphbench run`");
    ExpandOptions ex;
    for (const auto& [k, v] : parse_settings(a.settings)) ex.overrides.emplace_back(k, v);
    ex.scale = a.scale;
    ex.backend = a.backend;
    ex.gpu_available = cuda_backend_available();
    const std::vector<PlannedRun> runs = expand(spec, ex);
    const PlannedRun& first = runs.front();
    const bool reduced = first.reduced_scale;
    const bool host = first.solver.backend == BackendKind::host;
    if (reduced && host)
        std::printf("%s: no GPU run: reduced scale on the host backend (particles x%g, at most %ld steps instead of %ld)\n",
                    spec.name.c_str(), first.scale, first.steps, spec.steps);

    std::string overrides;
    for (const auto& kv : a.settings) overrides += (overrides.empty() ? "" : " ") + ("--set " + kv);
    if (a.scale != 1.0) overrides += (overrides.empty() ? "" : " ") + ("--scale " + format_number(a.scale));
    if (!a.backend.empty()) overrides += (overrides.empty() ? "" : " ") + ("--backend " + a.backend);
    Metadata meta = provenance(host ? "host" : "cuda", host ? "host" : cuda_device_summary(),
                               command_line_of(ctx.argc, ctx.argv));
    for (const auto& kv : Metadata{{"experiment", spec.name},
                                   {"reproduces", spec.reproduces},
                                   {"spec", spec.path},
                                   {"spec_hash", spec_hash(spec.path)},
                                   {"binary_hash", binary_hash()},
                                   {"overrides", overrides.empty() ? "none" : overrides},
                                   {"seed", std::to_string(spec.seed)},
                                   {"scale", format_number(first.scale)},
                                   {"reduced_scale", reduced ? "yes" : "no"},
                                   {"probe", spec.stability->probe},
                                   {"criterion", "stable = reaches target_time (or max_steps steps when it is 0) "
                                                 "without a blow-up: non-finite acceleration, fluid speed above c0, "
                                                 "or fluid density outside [0.5, 2] rho0"}})
        meta.push_back(kv);

    const std::string dir = experiment_dir(a.out, spec);
    const std::string summary = (fs::path(dir) / "summary.csv").string();
    if (!a.force && results_up_to_date(summary, meta)) {
        std::printf("%s: up to date (use --force to run again)\n", spec.name.c_str());
        ctx.exit_code = exit_ok;
        return;
    }
    fs::create_directories(dir);
    fs::remove(summary);  // only a finished study has one
    if (spec.stability->probe == "cfl-limit") cfl_limit_study(spec, runs, meta, dir, a.quiet);
    else energy_study(spec, runs, meta, dir, a.quiet);
    std::printf("wrote %s\n", summary.c_str());
    ctx.exit_code = exit_ok;
}

}  // namespace

void add_stability_command(CLI::App& app, CommandContext& ctx) {
    auto a = std::make_shared<StabilityArgs>();
    CLI::App* cmd = app.add_subcommand(
        "stability", "run a stability study (an experiment spec with [stability]): the largest stable CFL number by "
                     "bisection, or the drift of energy and free surface over a long run");
    cmd->add_option("spec", a->spec, "stability spec, e.g. experiments/stability-cfl.toml")->required();
    cmd->add_option("--set", a->settings, "override key=value in every run (repeatable), as for `sphbench run`");
    cmd->add_option("--scale", a->scale, "multiply every particle count by F (dp by F^(-1/3))")
        ->check(in_range(number_above(0)));
    cmd->add_option("--backend", a->backend, "cuda, host or auto (default: the spec's, else auto)")
        ->check(setting_validator("backend"));
    cmd->add_option("--out", a->out, "results folder; the study writes into DIR/<name>/")->capture_default_str();
    cmd->add_flag("--force", a->force, "run even when the results are up to date");
    cmd->add_flag("--quiet", a->quiet, "no progress line");
    cmd->callback([a, &ctx] { run_study(*a, ctx); });
}

}  // namespace sph
