// sphbench simulate SCENE: runs one scene for N steps, or to a simulated time, and reports its
// speed: over the whole run (seconds per simulated second) and per step over the window after
// the warm-up.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "case_file.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "gauge_options.hpp"
#include "scene_run.hpp"
#include "search_calibration.hpp"
#include "statistics.hpp"

namespace sph {
namespace {

struct SimulateArgs {
    std::string scene;
    std::vector<std::string> settings;
    std::vector<std::string> gauges;
    long steps = 0, warmup = 0, snapshot_every = 0;  // defaults: the run settings table's
    std::string out = "results/simulate";
    bool quiet = false;
    bool auto_search = false;
    double validate_every = 0, end_time = 0;  // end_time 0: none
    bool steps_given = false;
    SettingMap solver;  // the solver flags given, checked, by spec key
};

// Which rule ended the run, and when both could have, what the other one was.
std::string stop_reason(const SceneRunRequest& req, const SceneRunResult& r) {
    char text[160];
    if (r.stopped_by == "end_time")
        std::snprintf(text, sizeof text, "stopped at the end time %.6g s", req.end_time);
    else if (req.end_time > 0)
        std::snprintf(text, sizeof text, "stopped by the step cap (--steps %ld after %ld warm-up) before the end time %.6g s",
                      req.steps, req.warmup, req.end_time);
    else
        std::snprintf(text, sizeof text, "stopped after the steps asked for (--steps %ld after %ld warm-up)", req.steps,
                      req.warmup);
    return text;
}

void print_summary(const SceneRunRequest& req, const SceneRunResult& r) {
    std::vector<double> step_ms, update_ms, forces_ms, wall_ms;
    for (const auto& s : r.steps) {
        step_ms.push_back(s.step_ms());
        update_ms.push_back(s.update_ms());
        forces_ms.push_back(s.phase_ms[std::size_t(Phase::forces)]);
        wall_ms.push_back(s.wall_ms);
    }
    const Summary st = summarize(step_ms), up = summarize(update_ms), fo = summarize(forces_ms),
                  wall = summarize(wall_ms);
    const double pairs = r.work.samples ? double(r.work.neighbours) / double(r.work.samples) : 0;
    std::printf("scene %s on %s (%s): %zu particles (%zu fluid, %zu boundary), spacing %.6g m\n", req.scene.c_str(),
                r.device.c_str(), backend_name(req.solver.backend).c_str(), r.particles, r.fluid, r.boundary, r.dp);
    // The whole run first: what a user of the solver waits for.
    std::printf("run: %ld steps (%ld of them warm-up), simulated time %.6g s, %s\n", r.steps_taken,
                std::min(req.warmup, r.steps_taken), r.sim_time, stop_reason(req, r).c_str());
    if (r.sim_time > 0)
        std::printf("whole run: %.3f s wall, %.4g s per simulated second (every step, warm-up, rebuilds, sorts and "
                    "exchanges included)\n",
                    r.wall_seconds, r.seconds_per_sim_second());
    if (r.list_bytes > 0 && r.cost.steps > 0)  // Verlet lists, asked for or chosen by --auto-search
        std::printf("Verlet lists: %ld rebuilds in %ld steps (every %.1f steps); mean wall time of a rebuild step %.3f ms, "
                    "of a listed step %.3f ms (nan: no such step); lists %.0f bytes per particle\n",
                    r.cost.rebuild_steps, r.cost.steps,
                    r.cost.rebuild_steps > 0 ? double(r.cost.steps) / double(r.cost.rebuild_steps) : 0.0,
                    r.cost.rebuild_step_ms(), r.cost.listed_step_ms(), double(r.list_bytes) / double(r.particles));
    if (req.solver.variants != ImplementationVariants{})
        std::printf("implementation variants: %s%s\n", describe_implementation_variants(req.solver.variants).c_str(),
                    req.solver.backend == BackendKind::cuda ? "" : " (the host backend has one loop each: no effect)");
    if (r.steps.empty()) return;
    const StepRecord& last = r.steps.back();
    std::printf("window: %zu steps after the %ld warm-up, last dt %.3g s\n", r.steps.size(), req.warmup, last.dt);
    // The mean counts what the median hides: Verlet lists' rebuilds, a few steps in a hundred.
    std::printf("time per step in the window: median %.3f ms (quartiles %.3f to %.3f), mean %.3f ms; update (forces + "
                "integration) %.3f ms\n",
                st.median, st.q1, st.q3, st.mean, up.median);
    // With several subdomains the step's phases are those of the slowest subdomain: what the
    // decomposition takes when the subdomains run side by side (GPUs, MPI ranks). One process on
    // the host backend runs them one after another, so there its wall clock is the step's time.
    if (last.subdomain_ms.size() > 1)
        std::printf("wall time per step: median %.3f ms (the time per step above sums each phase's slowest "
                    "subdomain; host subdomains of one process run one after another)\n",
                    wall.median);
    std::printf("throughput: %.1f million particle-steps per second\n", double(r.particles) / (st.median * 1e3));
    std::printf("memory: %.0f bytes per particle (%.1f MiB allocated)\n",
                double(r.bytes_allocated) / double(r.particles), double(r.bytes_allocated) / 1048576.0);
    if (pairs > 0)
        std::printf("neighbour pairs: %.0f per step (%.1f per particle), %.3g pairs per second in the force loop\n",
                    pairs, pairs / double(r.particles), pairs / (fo.median * 1e-3));
    if (last.out_of_domain > 0)
        std::printf("warning: %zu fluid particles left the domain and were dropped\n", last.out_of_domain);
    if (!r.transport.empty()) std::printf("transport between subdomains: %s\n", r.transport.c_str());
    if (!r.rank_transport.empty()) std::printf("rank_transport: %s\n", r.rank_transport.c_str());
    if (!r.search_choice.empty())
        std::printf("search calibration (mean step over a run; Verlet lists: the listed step plus a rebuild's "
                    "extra cost over the expected steps between rebuilds): %s\n",
                    r.search_choice.c_str());
    for (const auto& [k, v] : r.validation_summary) std::printf("validation: %s = %.6g\n", k.c_str(), v);
    for (const auto& f : r.files) std::printf("wrote %s\n", f.c_str());
}

}  // namespace

void add_simulate_command(CLI::App& app, CommandContext& ctx) {
    auto args = std::make_shared<SimulateArgs>();
    CLI::App* cmd = app.add_subcommand(
        "simulate", "run one scene for N steps or to a simulated time (--end-time), show progress, report its speed: "
                    "seconds per simulated second over the whole run, time per step after the warm-up");
    cmd->add_option("scene", args->scene,
                    "scene name (see `sphbench info`), or case:FILE.toml, a case file: a tank, boxes of fluid, "
                    "obstacles and meshes in metres (experiments/cases/README.md), e.g. "
                    "case:experiments/cases/spheric-test2.toml --set dp=0.02")
        ->required();
    cmd->add_option("--set", args->settings, "scene option key=value (repeatable), e.g. particles=2980000");
    cmd->footer(
        "Case files (scene case:FILE.toml; experiments/cases/README.md): [case] dp, description, domain or "
        "domain_top, and scene options (kernel, c0_factor, alpha, delta, density_diffusion, gravity, rho0, coef_h, cfl); [case.tank] "
        "min, max, open_top, layers, name; [[case.fluid]] min, max, hydrostatic, velocity; [[case.obstacle]] name, "
        "min, max, layers; [[case.mesh]] file, height, min, up. Lengths in metres; --set dp=... and the scene "
        "options override the file's.");
    // The run settings' flags, from their table (solver_settings.hpp): the spec keys' ranges.
    for (auto [key, field] : {std::pair{"steps", &args->steps}, std::pair{"warmup", &args->warmup},
                              std::pair{"snapshot_every", &args->snapshot_every}}) {
        const RunSetting& s = run_setting(key);
        *field = std::stol(s.simulate_default);
        CLI::Option* o = cmd->add_option(setting_flag(s), *field, s.help)->check(in_range(s.range));
        if (*field != 0) o->capture_default_str();
        if (std::string(key) == "steps")
            o->description(std::string(s.help) + " (with --end-time: a cap, none unless given)")
                ->each([args](const std::string&) { args->steps_given = true; });
    }
    const RunSetting& end_time = run_setting("end_time");
    cmd->add_option(setting_flag(end_time), args->end_time, std::string(end_time.help) + ", for any scene")
        ->check(in_range(end_time.range));
    cmd->add_option("--out", args->out, "output folder")->capture_default_str();
    cmd->add_option("--gauge", args->gauges,
                    "a gauge sampled every EVERY simulated seconds into SCENE_gauges.csv (repeatable): "
                    "KIND:key=value,... with KIND pressure or velocity (x, y, z), water_level (x, y), max_height "
                    "(x, y, radius) or force (body: a body the scene names, e.g. tank); every kind takes every "
                    "(required) and name, e.g. --gauge water_level:x=0.6,y=0.335,every=0.01; a case file's gauges "
                    "are sampled too, and one named as a case gauge replaces it");
    cmd->add_flag("--quiet", args->quiet, "no progress line");
    cmd->add_flag("--auto-search", args->auto_search,
                  "time every search strategy for a few steps first, Verlet lists at four layouts and skins too "
                  "(their rebuilds weighed by how often the run will rebuild), and run the one a whole run costs "
                  "least with (overrides --merge, --cells-per-support, --verlet and --skin)");
    cmd->add_option("--validate", args->validate_every,
                    "evaluate the scene's validation metric every DT simulated seconds (dambreak: surge front against "
                    "Martin and Moyce; tank: hydrostatic pressure) into SCENE_validation.csv")
        ->check(in_range(number_above(0)));
    add_solver_options(*cmd, args->solver);
    cmd->callback([args, &ctx] {
        check_output_folder("--out", args->out);
        SceneRunRequest req;
        req.scene = args->scene;
        req.scene_options = parse_settings(args->settings);
        for (const std::string& g : args->gauges) req.gauges.push_back(parse_gauge_option(g));
        req.solver = solver_options(args->solver);
        // With an end time, --steps is a cap only when given.
        req.steps = args->end_time > 0 && !args->steps_given ? 0 : args->steps;
        req.warmup = args->warmup;
        req.end_time = args->end_time;
        req.snapshot_every = args->snapshot_every;
        req.out_dir = args->out;
        req.basename = scene_stem(args->scene);
        req.progress = !args->quiet;
        req.calibrate_search = args->auto_search;
        req.validation = {args->validate_every, args->end_time};
        req.metadata = provenance(backend_name(req.solver.backend),
                                  req.solver.backend == BackendKind::cuda ? cuda_device_summary() : "host",
                                  describe_implementation_variants(req.solver.variants),
                                  command_line_of(ctx.argc, ctx.argv));
        const SceneRunResult r = run_scene(req);
        print_summary(req, r);
        ctx.exit_code = exit_ok;
    });
}

}  // namespace sph
