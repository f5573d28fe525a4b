// sphbench simulate SCENE: runs one scene for N steps and reports its speed.
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
    double validate_every = 0, end_time = 0;
    SettingMap solver;  // the solver flags given, checked, by spec key
};

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
    if (r.steps.empty()) return;
    const StepRecord& last = r.steps.back();
    std::printf("%zu steps recorded after %ld warm-up, simulated time %.5g s, last dt %.3g s\n", r.steps.size(),
                req.warmup, last.time, last.dt);
    // The mean counts what the median hides: Verlet lists' rebuilds, a few steps in a hundred.
    std::printf("time per step: median %.3f ms (quartiles %.3f to %.3f), mean %.3f ms; update (forces + integration) "
                "%.3f ms\n",
                st.median, st.q1, st.q3, st.mean, up.median);
    if (req.solver.search.verlet) {
        std::size_t rebuilds = 0;
        for (const auto& s : r.steps) rebuilds += s.phase_ms[std::size_t(Phase::neighbour_list)] > 0;
        std::printf("Verlet lists: rebuilt in %zu of the %zu recorded steps\n", rebuilds, r.steps.size());
    }
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
        std::printf("search calibration (mean step; Verlet lists rebuilt every %d steps): %s\n",
                    verlet_trial_rebuild_every, r.search_choice.c_str());
    for (const auto& [k, v] : r.validation_summary) std::printf("validation: %s = %.6g\n", k.c_str(), v);
    for (const auto& f : r.files) std::printf("wrote %s\n", f.c_str());
}

}  // namespace

void add_simulate_command(CLI::App& app, CommandContext& ctx) {
    auto args = std::make_shared<SimulateArgs>();
    CLI::App* cmd = app.add_subcommand("simulate", "run one scene for N steps, show progress, report its speed");
    cmd->add_option("scene", args->scene,
                    "scene name (see `sphbench info`), or case:FILE.toml, a case file: a tank, boxes of fluid, "
                    "obstacles and meshes in metres (experiments/cases/README.md), e.g. "
                    "case:experiments/cases/spheric-test2.toml --set dp=0.02")
        ->required();
    cmd->add_option("--set", args->settings, "scene option key=value (repeatable), e.g. particles=2980000");
    cmd->footer(
        "Case files (scene case:FILE.toml; experiments/cases/README.md): [case] dp, description, domain or "
        "domain_top, and scene options (kernel, c0_factor, alpha, delta, gravity, rho0, coef_h, cfl); [case.tank] "
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
    }
    cmd->add_option("--out", args->out, "output folder")->capture_default_str();
    cmd->add_option("--gauge", args->gauges,
                    "a gauge sampled every EVERY simulated seconds into SCENE_gauges.csv (repeatable): "
                    "KIND:key=value,... with KIND pressure or velocity (x, y, z), water_level (x, y), max_height "
                    "(x, y, radius) or force (body: a body the scene names, e.g. tank); every kind takes every "
                    "(required) and name, e.g. --gauge water_level:x=0.6,y=0.335,every=0.01");
    cmd->add_flag("--quiet", args->quiet, "no progress line");
    cmd->add_flag("--auto-search", args->auto_search,
                  "time every search strategy for a few steps first, Verlet lists too (one subdomain), and run the "
                  "fastest (overrides --merge, --cells-per-support, --verlet and --skin)");
    auto* validate = cmd->add_option("--validate", args->validate_every,
                                     "evaluate the scene's validation metric every DT simulated seconds (dambreak: surge "
                                     "front against Martin and Moyce; tank: hydrostatic pressure) into SCENE_validation.csv")
                         ->check(in_range(number_above(0)));
    cmd->add_option("--end-time", args->end_time, "stop at this simulated time (--steps is then a cap)")
        ->check(in_range(number_above(0)))
        ->needs(validate);
    add_solver_options(*cmd, args->solver);
    cmd->callback([args, &ctx] {
        check_output_folder("--out", args->out);
        SceneRunRequest req;
        req.scene = args->scene;
        req.scene_options = parse_settings(args->settings);
        for (const std::string& g : args->gauges) req.gauges.push_back(parse_gauge_option(g));
        req.solver = solver_options(args->solver);
        req.steps = args->steps;
        req.warmup = args->warmup;
        req.snapshot_every = args->snapshot_every;
        req.out_dir = args->out;
        req.basename = scene_stem(args->scene);
        req.progress = !args->quiet;
        req.calibrate_search = args->auto_search;
        req.validation = {args->validate_every, args->end_time};
        req.metadata = provenance(backend_name(req.solver.backend),
                                  req.solver.backend == BackendKind::cuda ? cuda_device_summary() : "host",
                                  command_line_of(ctx.argc, ctx.argv));
        const SceneRunResult r = run_scene(req);
        print_summary(req, r);
        ctx.exit_code = exit_ok;
    });
}

}  // namespace sph
