#include "experiment_runner.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include "core/error.hpp"
#include "io/csv_writer.hpp"
#include "multi/rank_group.hpp"
#include "statistics.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> summary_stats = {"median", "q1", "q3", "min"};

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

std::vector<std::string> runs_csv_columns(const std::vector<PlannedRun>& runs) {
    std::vector<std::string> c = {"run_id", "config", "scene",     "repetition", "backend", "device",
                                  "particles", "fluid", "boundary", "dp",        "steps",   "warmup"};
    for (const auto& key : solver_setting_keys())
        if (key != "backend") c.push_back(key);
    std::set<std::string> options;  // the union over runs, sorted
    for (const auto& r : runs)
        for (const auto& [k, v] : r.scene_options) options.insert(k);
    for (const auto& k : options) c.push_back("set." + k);
    for (const auto& m : time_metrics())
        for (const auto& s : summary_stats) c.push_back(m + "_" + s);
    for (const char* k : {"mparticle_steps_per_s", "bytes_per_particle", "candidates_per_step", "neighbours_per_step",
                          "ranges_per_step", "sim_time", "wall_s", "steps_file"})
        c.emplace_back(k);
    // Validation columns only where a run asks for validation: each metric's summary once.
    std::set<std::string> metric_scenes;
    for (const auto& r : runs)
        if (r.validation.enabled()) metric_scenes.insert(r.scene);
    if (std::any_of(runs.begin(), runs.end(), [](const PlannedRun& r) { return r.record_blow_up; }))
        c.emplace_back("blow_up");
    if (!metric_scenes.empty()) {
        for (const char* k : {"validation_every", "validation_end_time", "steps_run", "validation_s", "validation_file"})
            c.emplace_back(k);
        for (const auto& m : validation_metrics())
            if (metric_scenes.count(m.scene))
                for (const auto& k : m.summary_columns) c.push_back(k);
    }
    return c;
}

std::vector<std::string> runs_csv_row(const std::vector<std::string>& columns, const PlannedRun& run,
                                      const SceneRunResult& r, const std::string& steps_file) {
    std::map<std::string, std::string> cell;
    cell["run_id"] = run.run_id;
    cell["config"] = run.config;
    cell["scene"] = run.scene;
    cell["repetition"] = std::to_string(run.repetition);
    cell["backend"] = run.solver.backend == BackendKind::cuda ? "cuda" : "host";
    cell["device"] = r.device;
    cell["particles"] = std::to_string(r.particles);
    cell["fluid"] = std::to_string(r.fluid);
    cell["boundary"] = std::to_string(r.boundary);
    cell["dp"] = format_number(r.dp);
    cell["steps"] = std::to_string(run.steps);
    cell["warmup"] = std::to_string(run.warmup);
    for (const auto& [k, v] : run.solver_settings) cell[k] = v;
    for (const auto& [k, v] : run.scene_options) cell["set." + k] = v;
    double step_median = 0;
    for (const auto& m : time_metrics()) {
        const Summary s = summarize(metric_series(r, m));
        cell[m + "_median"] = format_number(s.median);
        cell[m + "_q1"] = format_number(s.q1);
        cell[m + "_q3"] = format_number(s.q3);
        cell[m + "_min"] = format_number(s.min);
        if (m == "step_ms") step_median = s.median;
    }
    cell["mparticle_steps_per_s"] = step_median > 0 ? format_number(double(r.particles) / (step_median * 1e3)) : "";
    cell["bytes_per_particle"] = r.particles ? format_number(double(r.bytes_allocated) / double(r.particles)) : "";
    cell["candidates_per_step"] = per_step(r.work.candidates, r.work.samples);
    cell["neighbours_per_step"] = per_step(r.work.neighbours, r.work.samples);
    cell["ranges_per_step"] = per_step(r.work.ranges, r.work.samples);
    cell["sim_time"] = r.steps.empty() ? "0" : format_number(r.steps.back().time);
    cell["wall_s"] = format_number(r.wall_seconds);
    cell["steps_file"] = steps_file;
    cell["blow_up"] = r.blow_up;
    if (run.validation.enabled()) {
        cell["validation_every"] = format_number(run.validation.every);
        cell["validation_end_time"] = format_number(run.validation.end_time);
        cell["steps_run"] = std::to_string(r.steps.size());
        cell["validation_s"] = format_number(r.validation_seconds);
        for (const auto& f : r.files)
            if (f.size() >= 15 && f.compare(f.size() - 15, 15, "_validation.csv") == 0)
                cell["validation_file"] = fs::path(f).filename().string();
        for (const auto& [k, v] : r.validation_summary) cell[k] = format_number(v);
    }
    std::vector<std::string> row;
    for (const auto& c : columns) row.push_back(cell.count(c) ? cell[c] : "");
    return row;
}

SceneRunRequest scene_request(const ExperimentSpec& spec, const PlannedRun& run) {
    SceneRunRequest req;
    req.scene = run.scene;
    req.scene_options = run.scene_options;
    req.solver = run.solver;
    req.steps = run.steps;
    req.warmup = run.warmup;
    req.snapshot_every = spec.records("snapshots") ? run.snapshot_every : 0;
    req.count_work_every = spec.records("counters-every-step") ? 1 : 0;
    req.write_step_csv = spec.records("steps");
    req.basename = run.run_id;
    req.validation = run.validation;
    req.record_blow_up = run.record_blow_up;
    return req;
}

ExperimentOutcome run_experiment(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs,
                                 const ExperimentRunOptions& options) {
    const std::string dir = experiment_dir(options.out_dir, spec);
    ExperimentOutcome outcome;
    outcome.runs_csv = (fs::path(dir) / "runs.csv").string();
    std::error_code ec;
    const bool writing = process_ranks().rank() == 0;  // under MPI, rank 0 writes
    if (writing) fs::remove(outcome.runs_csv, ec);  // its step files are about to be replaced

    const std::vector<std::string> columns = runs_csv_columns(runs);
    std::vector<std::vector<std::string>> rows;
    const auto& handed_on = options.delegated.run_ids;
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const PlannedRun& run = runs[i];
        if (std::find(handed_on.begin(), handed_on.end(), run.run_id) != handed_on.end()) {
            rows.emplace_back();  // filled in below, by the other build
            continue;
        }
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
        }
        std::string steps_file;
        for (const auto& f : result.files) {
            outcome.files.push_back(f);
            if (f.size() >= 10 && f.compare(f.size() - 10, 10, "_steps.csv") == 0)
                steps_file = fs::path(f).filename().string();
        }
        rows.push_back(runs_csv_row(columns, run, result, steps_file));
        if (!options.quiet) {
            const Summary update = summarize(metric_series(result, "update_ms"));
            const Summary step = summarize(metric_series(result, "step_ms"));
            std::printf("[%zu/%zu] %s: %zu particles on %s, %zu steps, update %.3f ms, step %.3f ms (medians), %.1f s\n",
                        i + 1, runs.size(), run.run_id.c_str(), result.particles, result.device.c_str(),
                        result.steps.size(), update.median, step.median, result.wall_seconds);
            if (!result.blow_up.empty()) std::printf("    recorded, not fatal: %s\n", result.blow_up.c_str());
            for (const auto& [k, v] : result.validation_summary) std::printf("    %s = %.4g\n", k.c_str(), v);
            std::fflush(stdout);
        }
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
        CsvWriter table(outcome.runs_csv, columns, options.metadata);
        for (const auto& row : rows) table.row(row);
        table.commit();
    }
    outcome.files.push_back(outcome.runs_csv);
    return outcome;
}

}  // namespace sph
