#include "scene_run.hpp"

#include <cstdio>
#include <filesystem>
#include <new>
#include <optional>

#include "case_file.hpp"
#include "end_time_stop.hpp"
#include "gauge_options.hpp"
#include "gauge_sink.hpp"
#include "last_good_sink.hpp"
#include "multi/rank_group.hpp"
#include "out_of_memory.hpp"
#include "progress_sink.hpp"
#include "record_blow_up.hpp"
#include "run_loop.hpp"
#include "search_calibration.hpp"
#include "snapshot_sink.hpp"
#include "step_count_stop.hpp"
#include "step_csv_sink.hpp"
#include "step_recorder.hpp"
#include "validation_sink.hpp"

namespace sph {

// Experiments sweep solver settings over the same scene: building it once (filling a mesh of
// millions of particles takes seconds) and reusing it for the next run saves that each time.
static const Scene& built_scene(const std::string& name, const std::map<std::string, std::string>& options) {
    static std::string cached_key;
    static Scene cached;
    std::string key = name;
    for (const auto& [k, v] : options) key += "\n" + k + "=" + v;
    if (key != cached_key) {
        cached_key.clear();  // stays clear if building throws
        cached = build_scene(name, options);
        cached_key = key;
    }
    return cached;
}

SceneRunResult run_scene(const SceneRunRequest& request) {
    // A validation request's own end time stops the run too, where the request gives none.
    SceneRunRequest req = request;
    if (req.end_time <= 0 && req.validation.enabled()) req.end_time = req.validation.end_time;
    SceneRunResult res;
    const Scene& scene = built_scene(req.scene, req.scene_options);
    res.particles = scene.size();
    res.fluid = scene.fluid_count();
    res.boundary = scene.n_boundary;
    res.dp = scene.dp;
    res.scene_settings = scene.settings;
    // A case file's gauges, with the request's replacing those of their names (gauge_options.hpp).
    const std::vector<Gauge> gauges = merge_gauges(case_gauges(req.scene), req.gauges);
    for (const Gauge& g : gauges) check_gauge(g, scene);
    SolverOptions solver = req.solver;
    if (req.calibrate_search) {
        const Calibration cal = calibrate_search(scene, solver);
        solver.search = cal.best;
        char line[160];
        for (const auto& t : cal.trials) {
            if (t.search.verlet)
                std::snprintf(line, sizeof line, "%s%s=%.3fms(rebuild %.3f, listed %.3f, every %.1f)",
                              res.search_choice.empty() ? "" : " ", search_label(t.search).c_str(), t.mean_step_ms,
                              t.rebuild_step_ms, t.listed_step_ms, t.rebuild_interval);
            else
                std::snprintf(line, sizeof line, "%s%s=%.3fms", res.search_choice.empty() ? "" : " ",
                              search_label(t.search).c_str(), t.mean_step_ms);
            res.search_choice += line;
        }
        res.search_choice = "chose " + search_label(cal.best) + "; " + res.search_choice;
        if (!cal.verlet_skipped.empty()) res.search_choice += " (no Verlet lists: " + cal.verlet_skipped + ")";
    }
    std::optional<Simulation> started;
    try {
        started.emplace(scene, solver);
    } catch (const std::bad_alloc&) {
        // One sentence instead of "std::bad_alloc"; a GPU's memory is checked before it is
        // allocated (make_cuda_subdomain), the host's only fails.
        throw RunError("scene '" + req.scene + "' (" + std::to_string(scene.size()) +
                       " particles) does not fit this machine's host memory: it ran out while allocating the run's "
                       "particle arrays; " + coarser_scene_advice);
    }
    Simulation& sim = *started;
    res.device = sim.device_name();
    res.transport = sim.transport_name();
    if (!sim.transport_note().empty()) res.transport += " (" + sim.transport_note() + ")";
    res.rank_transport = sim.rank_transport_name();
    if (!sim.rank_transport_note().empty()) res.rank_transport += " (" + sim.rank_transport_note() + ")";
    res.bytes_allocated = sim.bytes_allocated();

    namespace fs = std::filesystem;
    // Under MPI every rank holds the whole record; rank 0 alone writes it.
    const bool writing = !req.out_dir.empty() && process_ranks().rank() == 0;
    auto out_path = [&](const std::string& suffix) { return (fs::path(req.out_dir) / (req.basename + suffix)).string(); };
    auto scene_metadata = [&] {
        Metadata meta = req.metadata;
        meta.emplace_back("scene", req.scene);
        for (const auto& [k, v] : res.scene_settings) meta.emplace_back("scene." + k, v);
        return meta;
    };

    // With an end time the step budget is a cap (none when steps is 0); the first rule reached
    // ends the run.
    const bool capped = req.end_time <= 0 || req.steps > 0;
    const long total = capped ? req.warmup + req.steps : 0;
    RunLoop loop(sim, req.warmup);
    std::optional<StepCountStop> budget;
    if (capped) loop.stop_when(budget.emplace(total));
    std::optional<EndTimeStop> end_time;
    if (req.end_time > 0) loop.stop_when(end_time.emplace(req.end_time));
    RecordBlowUp record_blow_up;
    if (req.record_blow_up) loop.stop_when(record_blow_up);

    // Sinks are told in this order: the files are listed as they were written.
    StepRecorder steps;
    RunCostSink cost;
    WorkCounterSink work(req.count_work_every);
    loop.feed(steps).feed(cost).feed(work);
    // A snapshot gathers every rank's particles, so every rank takes it; rank 0 writes it.
    std::optional<SnapshotSink> snapshots;
    if (!req.out_dir.empty() && req.snapshot_every > 0)
        loop.feed(snapshots.emplace(req.snapshot_every, writing ? out_path("_snapshots") : "", req.basename));
    std::optional<ValidationSink> validation;
    if (req.validation.enabled())
        loop.feed(validation.emplace(scene, req.validation, writing ? out_path("_validation.csv") : "", scene_metadata()));
    std::optional<GaugeSink> gauge_sink;
    if (!gauges.empty()) loop.feed(gauge_sink.emplace(gauges, writing ? out_path("_gauges.csv") : "", scene_metadata()));
    ProgressSink progress(req.scene, total, req.end_time, req.progress);
    loop.feed(progress);
    std::optional<LastGoodSink> last_good;
    if (writing) loop.feed(last_good.emplace(fs::path(req.out_dir).string(), req.basename));
    std::optional<StepCsvSink> step_csv;
    if (writing && req.write_step_csv) {
        Metadata meta = scene_metadata();
        meta.emplace_back("particles", std::to_string(res.particles));
        meta.emplace_back("device", res.device);
        if (!res.transport.empty()) meta.emplace_back("transport", res.transport);
        if (!res.rank_transport.empty()) meta.emplace_back("rank_transport", res.rank_transport);
        if (!res.search_choice.empty()) meta.emplace_back("search_calibration", res.search_choice);
        loop.feed(step_csv.emplace(steps, out_path("_steps.csv"), meta, res.boundary));
    }

    const RunLoopOutcome out = loop.run();
    res.wall_seconds = out.wall_seconds;
    res.steps_taken = out.steps;
    res.sim_time = out.time;
    res.end_time = req.end_time;
    res.stopped_by = out.blow_up ? "blow_up" : req.end_time > 0 && out.time >= req.end_time ? "end_time" : "steps";
    res.cost = cost.cost();
    if (solver.search.verlet) res.list_bytes = sim.neighbour_list_bytes();
    if (out.blow_up) res.blow_up = out.blow_up->message + out.blow_up->where;  // a result of the study
    res.steps = steps.take();
    res.work = work.totals();
    if (snapshots)
        for (const auto& f : snapshots->files()) res.files.push_back(f);
    if (validation) {
        res.validation_summary = validation->summary();
        res.validation_seconds = validation->seconds();
        if (!validation->file().empty()) res.files.push_back(validation->file());
    }
    if (gauge_sink && !gauge_sink->path().empty()) res.files.push_back(gauge_sink->path());
    if (step_csv) res.files.push_back(step_csv->path());
    return res;
}

}  // namespace sph
