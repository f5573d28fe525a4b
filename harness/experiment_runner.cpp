#include "experiment_runner.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <new>
#include <set>

#include "core/error.hpp"
#include "csv_table.hpp"
#include "io/csv_writer.hpp"
#include "multi/rank_group.hpp"
#include "out_of_memory.hpp"
#include "statistics.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

// A per-step mean of a counter: an integer where the division is exact.
std::string per_step(unsigned long long total, long samples) {
    if (samples <= 0) return "";
    if (total % static_cast<unsigned long long>(samples) == 0) return std::to_string(total / static_cast<unsigned long long>(samples));
    return format_number(double(total) / double(samples));
}

std::vector<double> metric_series(const SceneRunResult& r, const std::string& metric) {
    std::vector<double> out;
    out.reserve(r.steps.size());
    for (const auto& s : r.steps) {
        if (metric == "update_ms") {
            out.push_back(s.update_ms());
        } else if (metric == "update_ideal_ms") {
            out.push_back(s.update_ideal_ms());
        } else if (metric == "step_ms") {
            out.push_back(s.step_ms());
        } else if (metric == "wall_ms") {
            out.push_back(s.wall_ms);
        } else {
            for (std::size_t p = 0; p < phase_count; ++p)
                if (metric == std::string(phase_names[p]) + "_ms") out.push_back(s.phase_ms[p]);
        }
    }
    return out;
}

}  // namespace

std::vector<std::string> time_metrics() {
    std::vector<std::string> m = {"update_ms", "update_ideal_ms", "step_ms", "wall_ms"};
    for (const char* p : phase_names) m.push_back(std::string(p) + "_ms");
    return m;
}

const std::vector<std::string>& counter_columns() {
    static const std::vector<std::string> c = {"particles",           "fluid",           "boundary",
                                               "candidates_per_step", "neighbours_per_step", "ranges_per_step"};
    return c;
}

std::string experiment_dir(const std::string& out_dir, const ExperimentSpec& spec) {
    return (fs::path(out_dir) / spec.name).string();
}

RunsRow::RunsRow(const PlannedRun& p, const SceneRunResult& r, std::string steps)
    : run(p), result(r), steps_file(std::move(steps)) {
    for (const auto& m : time_metrics()) times.push_back(summarize(metric_series(r, m)));
}

ColumnTable<RunsRow> runs_table(const std::vector<PlannedRun>& runs) {
    using R = const RunsRow&;
    auto whole = [](auto v) { return std::to_string(v); };
    ColumnTable<RunsRow> t;
    t.add("run_id", [](R r) { return r.run.run_id; })
        .add("config", [](R r) { return r.run.config; })
        .add("scene", [](R r) { return r.run.scene; })
        .add("repetition", [whole](R r) { return whole(r.run.repetition); })
        // The setting as the spec gave it ("auto" too), as this table always had it.
        .add("backend", [](R r) { return r.run.solver_settings.at("backend"); })
        .add("device", [](R r) { return r.result.device; })
        // How particles between MPI ranks travelled: "" in one process (multi/rank_staging.hpp).
        .add("rank_transport", [](R r) { return r.result.rank_transport; })
        .add("particles", [whole](R r) { return whole(r.result.particles); })
        .add("fluid", [whole](R r) { return whole(r.result.fluid); })
        .add("boundary", [whole](R r) { return whole(r.result.boundary); })
        .add("dp", [](R r) { return format_number(r.result.dp); });
    // The whole run, from t = 0 and warm-up included: what a user waits for (issue 25). Empty
    // where a figure does not apply (no end time; no Verlet lists).
    const auto verlet_only = [](auto cell) {
        return [cell](R r) { return r.run.solver.search.verlet ? cell(r) : std::string(); };
    };
    t.add("end_time", [](R r) { return r.run.end_time > 0 ? format_number(r.run.end_time) : std::string(); })
        .add("steps", [whole](R r) { return whole(r.result.steps_taken); })
        .add("warmup", [whole](R r) { return whole(r.run.warmup); })
        .add("window_steps", [whole](R r) { return whole(r.result.steps.size()); })
        .add("stopped_by", [](R r) { return r.result.stopped_by; })
        .add("sim_time", [](R r) { return format_number(r.result.sim_time); })
        .add("wall_s", [](R r) { return format_number(r.result.wall_seconds); })
        .add("s_per_sim_s",
             [](R r) { return r.result.sim_time > 0 ? format_number(r.result.seconds_per_sim_second()) : std::string(); })
        .add("list_rebuilds", verlet_only([whole](R r) { return whole(r.result.cost.rebuild_steps); }))
        .add("rebuild_step_ms", verlet_only([](R r) { return format_number(r.result.cost.rebuild_step_ms()); }))
        .add("listed_step_ms", verlet_only([](R r) { return format_number(r.result.cost.listed_step_ms()); }))
        .add("list_bytes_per_particle", verlet_only([](R r) {
                 return r.result.particles ? format_number(double(r.result.list_bytes) / double(r.result.particles))
                                           : std::string();
             }));
    auto text_of = [](const std::map<std::string, std::string>& m, const std::string& key) {
        const auto it = m.find(key);
        return it == m.end() ? std::string() : it->second;
    };
    for (const auto& key : solver_setting_keys())
        if (key != "backend") t.add(key, [key, text_of](R r) { return text_of(r.run.solver_settings, key); });
    std::set<std::string> options;  // the union over runs, sorted
    for (const auto& r : runs)
        for (const auto& [k, v] : r.scene_options) options.insert(k);
    for (const auto& k : options) t.add("set." + k, [k, text_of](R r) { return text_of(r.run.scene_options, k); });
    const std::vector<std::string> metrics = time_metrics();
    std::size_t step_ms = 0;
    for (std::size_t m = 0; m < metrics.size(); ++m) {
        if (metrics[m] == "step_ms") step_ms = m;
        t.add(metrics[m] + "_median", [m](R r) { return format_number(r.times[m].median); })
            .add(metrics[m] + "_q1", [m](R r) { return format_number(r.times[m].q1); })
            .add(metrics[m] + "_q3", [m](R r) { return format_number(r.times[m].q3); })
            .add(metrics[m] + "_min", [m](R r) { return format_number(r.times[m].min); });
    }
    t.add("mparticle_steps_per_s",
          [step_ms](R r) {
              const double median = r.times[step_ms].median;
              return median > 0 ? format_number(double(r.result.particles) / (median * 1e3)) : "";
          })
        .add("bytes_per_particle",
             [](R r) {
                 return r.result.particles ? format_number(double(r.result.bytes_allocated) / double(r.result.particles))
                                           : "";
             })
        .add("candidates_per_step", [](R r) { return per_step(r.result.work.candidates, r.result.work.samples); })
        .add("neighbours_per_step", [](R r) { return per_step(r.result.work.neighbours, r.result.work.samples); })
        .add("ranges_per_step", [](R r) { return per_step(r.result.work.ranges, r.result.work.samples); })
        .add("steps_file", [](R r) { return r.steps_file; });
    if (std::any_of(runs.begin(), runs.end(), [](const PlannedRun& r) { return r.record_blow_up; }))
        t.add("blow_up", [](R r) { return r.result.blow_up; });
    // Validation columns only where a run asks for validation: each metric's summary once.
    std::set<std::string> metric_scenes;
    for (const auto& r : runs)
        if (r.validation.enabled()) metric_scenes.insert(r.scene);
    if (metric_scenes.empty()) return t;
    // Empty for a run without validation.
    auto validated = [](auto cell) {
        return [cell](R r) { return r.run.validation.enabled() ? cell(r) : std::string(); };
    };
    t.add("validation_every", validated([](R r) { return format_number(r.run.validation.every); }))
        .add("validation_end_time", validated([](R r) { return format_number(r.run.validation.end_time); }))
        .add("steps_run", validated([whole](R r) { return whole(r.result.steps.size()); }))
        .add("validation_s", validated([](R r) { return format_number(r.result.validation_seconds); }))
        .add("validation_file", validated([](R r) {
                 std::string name;
                 for (const auto& f : r.result.files)
                     if (f.size() >= 15 && f.compare(f.size() - 15, 15, "_validation.csv") == 0)
                         name = fs::path(f).filename().string();
                 return name;
             }));
    for (const auto& m : validation_metrics())
        if (metric_scenes.count(m.scene))
            for (const auto& k : m.summary_columns)
                t.add(k, validated([k](R r) {
                          for (const auto& [key, v] : r.result.validation_summary)
                              if (key == k) return format_number(v);
                          return std::string();
                      }));
    return t;
}

std::vector<std::string> runs_csv_columns(const std::vector<PlannedRun>& runs) { return runs_table(runs).names(); }

const char* runs_columns_note() {
    return "steps, sim_time, wall_s, s_per_sim_s, list_rebuilds, rebuild_step_ms and listed_step_ms cover the whole run "
           "from t = 0, warm-up included (the two step times are means of the steps' wall clocks); the <metric>_median, "
           "_q1, _q3 and _min columns summarise only the window of window_steps steps after the warm-up";
}

SceneRunRequest scene_request(const ExperimentSpec& spec, const PlannedRun& run) {
    SceneRunRequest req;
    req.scene = run.scene;
    req.scene_options = run.scene_options;
    req.solver = run.solver;
    req.steps = run.steps;
    req.warmup = run.warmup;
    req.end_time = run.end_time;
    req.snapshot_every = spec.records("snapshots") ? run.snapshot_every : 0;
    req.count_work_every = spec.records("counters-every-step") ? 1 : 0;
    req.write_step_csv = spec.records("steps");
    req.basename = run.run_id;
    req.validation = run.validation;
    req.record_blow_up = run.record_blow_up;
    req.gauges = spec.gauges;
    return req;
}

namespace {

// Runs one planned run into `dir` and gives its row of runs.csv; appends the files it wrote.
std::vector<std::string> run_one(const ExperimentSpec& spec, const PlannedRun& run, const ColumnTable<RunsRow>& table,
                                 const std::string& dir, const ExperimentRunOptions& options, std::size_t i,
                                 std::size_t count, std::vector<std::string>& files) {
    SceneRunRequest req = scene_request(spec, run);
    req.out_dir = dir;
    req.progress = !options.quiet;
    req.metadata = options.metadata;
    req.metadata.emplace_back("run_id", run.run_id);
    SceneRunResult result;
    try {
        result = run_scene(req);
    } catch (const InputError& e) {
        throw InputError("run '" + run.run_id + "' of " + spec.path + " failed: " + e.what());
    } catch (const RunError& e) {
        throw RunError("run '" + run.run_id + "' of " + spec.path + " failed: " + e.what());
    } catch (const std::bad_alloc&) {  // arrays that grew during the run (see sphbench.cpp)
        throw RunError("run '" + run.run_id + "' of " + spec.path + " failed: it ran out of host memory during the run; " +
                       coarser_scene_advice);
    }
    std::string steps_file;
    for (const auto& f : result.files) {
        files.push_back(f);
        if (f.size() >= 10 && f.compare(f.size() - 10, 10, "_steps.csv") == 0) steps_file = fs::path(f).filename().string();
    }
    std::vector<std::string> row = table.cells(RunsRow(run, result, steps_file));
    if (!options.quiet) {
        const Summary update = summarize(metric_series(result, "update_ms"));
        const Summary step = summarize(metric_series(result, "step_ms"));
        std::printf("[%zu/%zu] %s: %zu particles on %s, %ld steps to t = %.4g s (stopped by %s), %.1f s, %.4g s per "
                    "simulated second; window of %zu steps: update %.3f ms, step %.3f ms (medians)\n",
                    i + 1, count, run.run_id.c_str(), result.particles, result.device.c_str(), result.steps_taken,
                    result.sim_time, result.stopped_by.c_str(), result.wall_seconds, result.seconds_per_sim_second(),
                    result.steps.size(), update.median, step.median);
        if (run.solver.search.verlet)
            std::printf("    Verlet lists: %ld rebuilds in %ld steps; rebuild step %.3f ms, listed step %.3f ms (means; "
                        "nan: no such step)\n",
                        result.cost.rebuild_steps, result.cost.steps, result.cost.rebuild_step_ms(),
                        result.cost.listed_step_ms());
        if (!result.blow_up.empty()) std::printf("    recorded, not fatal: %s\n", result.blow_up.c_str());
        for (const auto& [k, v] : result.validation_summary) std::printf("    %s = %.4g\n", k.c_str(), v);
        std::fflush(stdout);
    }
    return row;
}

}  // namespace

ExperimentOutcome run_experiment(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs,
                                 const ExperimentRunOptions& options) {
    const std::string dir = experiment_dir(options.out_dir, spec);
    ExperimentOutcome outcome;
    outcome.runs_csv = (fs::path(dir) / "runs.csv").string();
    std::error_code ec;
    const bool writing = process_ranks().rank() == 0;  // under MPI, rank 0 writes
    if (writing) fs::remove(outcome.runs_csv, ec);  // its step files are about to be replaced

    const ColumnTable<RunsRow> table = runs_table(runs);
    const std::vector<std::string> columns = table.names();
    std::vector<std::vector<std::string>> rows;
    const auto& handed_on = options.delegated.run_ids;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const PlannedRun& run = runs[i];
        if (std::find(handed_on.begin(), handed_on.end(), run.run_id) != handed_on.end()) {
            rows.emplace_back();  // filled in below, by the other build
            continue;
        }
        rows.push_back(run_one(spec, run, table, dir, options, i, runs.size(), outcome.files));
    }
    if (!handed_on.empty()) {
        if (!options.quiet)
            std::printf("%zu run(s) in %s: handing them to %s\n", handed_on.size(),
                        options.delegated.binary.find("f64") != std::string::npos ? "float64" : "the other precision",
                        options.delegated.binary.c_str());
        auto delegated = run_delegated(options.delegated, spec, dir, columns, options.quiet);
        for (std::size_t i = 0; i < runs.size(); ++i)
            if (rows[i].empty()) rows[i] = delegated.at(runs[i].run_id);
    }
    if (writing) {
        Metadata meta = options.metadata;
        meta.emplace_back("columns", runs_columns_note());
        CsvWriter table(outcome.runs_csv, columns, meta);
        for (const auto& row : rows) table.row(row);
        table.commit();
    }
    outcome.files.push_back(outcome.runs_csv);
    return outcome;
}

ExperimentOutcome append_runs(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs_so_far,
                              const std::vector<PlannedRun>& more, const ExperimentRunOptions& options) {
    const std::string dir = experiment_dir(options.out_dir, spec);
    ExperimentOutcome outcome;
    outcome.runs_csv = (fs::path(dir) / "runs.csv").string();
    const CsvTable old = read_csv(outcome.runs_csv);
    std::vector<PlannedRun> all = runs_so_far;
    all.insert(all.end(), more.begin(), more.end());
    const ColumnTable<RunsRow> table = runs_table(all);
    const std::vector<std::string> columns = table.names();
    if (old.columns != columns)
        throw InputError("'" + outcome.runs_csv + "' has other columns than this experiment writes now; run it again "
                         "(--force) before adding repetitions to it");
    std::vector<std::vector<std::string>> rows = old.rows;
    for (std::size_t i = 0; i < more.size(); ++i)
        rows.push_back(run_one(spec, more[i], table, dir, options, i, more.size(), outcome.files));
    if (process_ranks().rank() == 0) {
        CsvWriter writer(outcome.runs_csv, columns, options.metadata);
        for (const auto& row : rows) writer.row(row);
        writer.commit();
    }
    outcome.files.push_back(outcome.runs_csv);
    return outcome;
}

}  // namespace sph
