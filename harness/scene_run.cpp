#include "scene_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <filesystem>

#include "io/csv_writer.hpp"
#include "multi/rank_group.hpp"
#include "progress.hpp"
#include "search_calibration.hpp"

namespace sph {

std::vector<std::string> step_csv_columns() {
    std::vector<std::string> c = {"step", "time", "dt", "fluid", "boundary", "out_of_domain", "kinetic_energy",
                                  "max_speed", "min_density", "max_density"};
    for (const char* p : phase_names) c.push_back(std::string(p) + "_ms");
    // update_ms is the paper's real wall time: the slowest subdomain's forces plus integration;
    // update_ideal_ms is the mean over subdomains (paper Fig. 5 and 8).
    for (const char* k : {"update_ms", "update_ideal_ms", "step_ms", "wall_ms", "subdomains", "slices_moved", "particles_migrated",
                          "ghosts_sent", "bytes_exchanged", "subdomain_update_ms", "subdomain_particles", "transfer_ms"})
        c.push_back(k);
    return c;
}

std::vector<std::string> step_csv_row(const StepRecord& r, const SceneRunResult& res) {
    auto f = [](double v) { return CsvWriter::fmt(v); };
    std::vector<std::string> row = {std::to_string(r.step),
                                    f(r.time),
                                    f(r.dt),
                                    std::to_string(r.stats.fluid_count),
                                    std::to_string(res.boundary),
                                    std::to_string(r.out_of_domain),
                                    f(r.stats.kinetic_energy),
                                    f(std::sqrt(double(r.stats.max_speed2))),
                                    f(r.stats.min_density),
                                    f(r.stats.max_density)};
    double total = 0;
    for (double t : r.phase_ms) {
        row.push_back(f(t));
        total += t;
    }
    double real_ms = 0, sum_ms = 0;
    std::string per_update, per_particles;
    for (std::size_t d = 0; d < r.subdomain_ms.size(); ++d) {
        const double u = update_time(r.subdomain_ms[d]);
        real_ms = std::max(real_ms, u);
        sum_ms += u;
        per_update += (d ? ";" : "") + f(u);
        per_particles += (d ? ";" : "") + std::to_string(r.subdomain_particles[d]);
    }
    const std::size_t n = std::max<std::size_t>(1, r.subdomain_ms.size());
    row.push_back(f(real_ms));
    row.push_back(f(sum_ms / double(n)));
    row.push_back(f(total));
    row.push_back(f(r.wall_ms));
    row.push_back(std::to_string(n));
    row.push_back(std::to_string(r.slices_moved));
    row.push_back(std::to_string(r.exchange.particles_migrated));
    row.push_back(std::to_string(r.exchange.ghosts_sent));
    row.push_back(std::to_string(r.exchange.bytes));
    row.push_back(per_update);
    row.push_back(per_particles);
    row.push_back(f(r.transfer_ms));
    return row;
}

// Experiments sweep solver settings over the same scene: building it once (filling a mesh of
// millions of particles takes seconds) and reusing it for the next run saves that each time.
static const Scene& built_scene(const std::string& name, const std::map<std::string, std::string>& options) {
    static std::string cached_key;
    static Scene cached;
    std::string key = name;
    for (const auto& [k, v] : options) key += "\n" + k + "=" + v;
    if (key != cached_key) {
        cached_key.clear();  // stays clear if building throws
        cached = make_scene(name, options);
        cached_key = key;
    }
    return cached;
}

SceneRunResult run_scene(const SceneRunRequest& req) {
    SceneRunResult res;
    const Scene& scene = built_scene(req.scene, req.scene_options);
    res.particles = scene.size();
    res.fluid = scene.fluid_count();
    res.boundary = scene.n_boundary;
    res.dp = scene.dp;
    res.scene_settings = scene.settings;
    SolverOptions solver = req.solver;
    if (req.calibrate_search) {
        const Calibration cal = calibrate_search(scene, solver);
        solver.search = cal.best;
        char line[96];
        for (const auto& t : cal.trials) {
            std::snprintf(line, sizeof line, "%sn%d%s=%.3fms", res.search_choice.empty() ? "" : " ",
                          t.search.cells_per_support, t.search.merge ? "m" : "", t.median_step_ms);
            res.search_choice += line;
        }
        std::snprintf(line, sizeof line, "chose n%d%s; ", cal.best.cells_per_support, cal.best.merge ? "m" : "");
        res.search_choice = line + res.search_choice;
    }
    Simulation sim(scene, solver);
    res.device = sim.device_name();
    res.transport = sim.transport_name();
    if (!sim.transport_note().empty()) res.transport += " (" + sim.transport_note() + ")";
    res.bytes_allocated = sim.bytes_allocated();

    namespace fs = std::filesystem;
    // Under MPI every rank holds the whole record; rank 0 alone writes it.
    const bool writing = !req.out_dir.empty() && process_ranks().rank() == 0;
    // A snapshot gathers every rank's particles, so every rank takes it; rank 0 writes it.
    const bool snapshotting = !req.out_dir.empty() && req.snapshot_every > 0;
    std::unique_ptr<SnapshotSeries> snapshots;
    if (writing && snapshotting)
        snapshots = std::make_unique<SnapshotSeries>((fs::path(req.out_dir) / (req.basename + "_snapshots")).string(),
                                                     req.basename);
    auto take_snapshot = [&] {
        const SnapshotData s = sim.snapshot();
        if (snapshots) snapshots->write(s);
    };
    if (snapshotting) take_snapshot();
    std::unique_ptr<ValidationRecorder> validation;
    if (req.validation.enabled()) {
        validation = std::make_unique<ValidationRecorder>(scene, req.validation);
        validation->sample(sim.snapshot());
    }
    const double end_time = req.validation.enabled() ? req.validation.end_time : 0.0;

    const long total = req.warmup + req.steps;
    Progress progress(req.scene, total, req.progress);
    const auto t0 = std::chrono::steady_clock::now();
    try {
        for (long k = 1; k <= total; ++k) {
            const StepRecord& r = sim.step();
            const bool recorded = k > req.warmup;
            if (recorded) {
                res.steps.push_back(r);
                const bool last = k == total;
                const bool count = req.count_work_every > 0 ? (k - req.warmup) % req.count_work_every == 0 : last;
                if (count) {
                    const WorkCounters w = sim.count_work();
                    res.work.candidates += w.candidates;
                    res.work.neighbours += w.neighbours;
                    res.work.ranges += w.ranges;
                    ++res.work.samples;
                }
            }
            if (snapshotting && k % req.snapshot_every == 0) take_snapshot();
            const bool ended = end_time > 0 && r.time >= end_time;
            if (validation && (ended || k == total || validation->due(r.time))) {
                const auto v0 = std::chrono::steady_clock::now();
                validation->sample(sim.snapshot());
                res.validation_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - v0).count();
            }
            char detail[96];
            std::snprintf(detail, sizeof detail, "t = %.4f s, %.2f ms/step", r.time, update_time(r.phase_ms));
            progress.update(k, detail);
            if (ended) break;
        }
    } catch (const BlowUpError& e) {
        progress.finish();
        std::string where;
        if (writing) {
            SnapshotSeries last((fs::path(req.out_dir)).string(), req.basename + "_last_good");
            last.write(e.last_good);
            where = "; the last good state is in " + last.xdmf_path();
        }
        if (!req.record_blow_up) {
            if (writing) throw RunError(std::string(e.what()) + where);
            throw;
        }
        res.blow_up = std::string(e.what()) + where;  // a result of the study, not a failure of the run
    }
    progress.finish();
    res.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (snapshots) {
        for (const auto& f : snapshots->files()) res.files.push_back(f);
        res.files.push_back(snapshots->xdmf_path());
    }
    if (validation) {
        res.validation_summary = validation->summary();
        if (writing) {
            Metadata meta = req.metadata;
            meta.emplace_back("scene", req.scene);
            for (const auto& [k, v] : res.scene_settings) meta.emplace_back("scene." + k, v);
            const std::string path = (fs::path(req.out_dir) / (req.basename + "_validation.csv")).string();
            res.files.push_back(validation->write_csv(path, meta));
        }
    }
    if (writing && req.write_step_csv) {
        Metadata meta = req.metadata;
        meta.emplace_back("scene", req.scene);
        for (const auto& [k, v] : res.scene_settings) meta.emplace_back("scene." + k, v);
        meta.emplace_back("particles", std::to_string(res.particles));
        meta.emplace_back("device", res.device);
        if (!res.transport.empty()) meta.emplace_back("transport", res.transport);
        if (!res.search_choice.empty()) meta.emplace_back("search_calibration", res.search_choice);
        const std::string path = (fs::path(req.out_dir) / (req.basename + "_steps.csv")).string();
        CsvWriter csv(path, step_csv_columns(), meta);
        for (const auto& r : res.steps) csv.row(step_csv_row(r, res));
        csv.commit();
        res.files.push_back(path);
    }
    return res;
}

}  // namespace sph
