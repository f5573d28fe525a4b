#pragma once
// Runs the expanded runs of an experiment one after another and writes its table,
// <out>/<name>/runs.csv: one row per run with its settings, timing summaries and work
// counters. The table is written last and atomically, so only a finished experiment has one.
#include <string>
#include <vector>

#include "column_table.hpp"
#include "experiment_spec.hpp"
#include "precision_delegate.hpp"
#include "provenance.hpp"
#include "scene_run.hpp"
#include "statistics.hpp"

namespace sph {

struct ExperimentRunOptions {
    std::string out_dir = "results";
    bool quiet = false;
    Metadata metadata;  // provenance and spec lines for every file written
    DelegatedRuns delegated;  // runs of the other precision, run by its build
};

struct ExperimentOutcome {
    std::string runs_csv;
    std::vector<std::string> files;
};

// The folder an experiment writes into: <out_dir>/<name>.
std::string experiment_dir(const std::string& out_dir, const ExperimentSpec& spec);

// Throws InputError or RunError naming the run that failed; runs.csv is then not written
// (and a previous one is removed first, since its step files are being replaced).
ExperimentOutcome run_experiment(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs,
                                 const ExperimentRunOptions& options);

// Runs `more` (further repetitions of runs in the experiment's runs.csv) and rewrites that
// table, atomically, with their rows after its own. Throws InputError when the table's columns
// are not those of runs_so_far plus more, and as run_experiment does when a run fails.
ExperimentOutcome append_runs(const ExperimentSpec& spec, const std::vector<PlannedRun>& runs_so_far,
                              const std::vector<PlannedRun>& more, const ExperimentRunOptions& options);

// The run's request to run_scene, with the spec's recording choices.
SceneRunRequest scene_request(const ExperimentSpec& spec, const PlannedRun& run);

// One row of runs.csv: a run, its result, and its time metrics' summaries (computed once).
struct RunsRow {
    RunsRow(const PlannedRun& run, const SceneRunResult& result, std::string steps_file);
    const PlannedRun& run;
    const SceneRunResult& result;
    std::string steps_file;
    std::vector<Summary> times;  // in the order of time_metrics()
};
// The columns of runs.csv, each beside its value: the settings and sizes; the whole run from
// t = 0 (end_time, steps, warmup, window_steps, stopped_by, sim_time, wall_s, s_per_sim_s, and
// with Verlet lists list_rebuilds, rebuild_step_ms, listed_step_ms, list_bytes_per_particle);
// the solver keys, the scene options of any run, each time metric's median, quartiles and
// minimum over the window after the warm-up, throughput, counters; blow_up where a run records
// blow-ups; validation columns where a run validates.
ColumnTable<RunsRow> runs_table(const std::vector<PlannedRun>& runs);
std::vector<std::string> runs_csv_columns(const std::vector<PlannedRun>& runs);
// The provenance line "columns" of runs.csv: which columns are of the whole run, which of the window.
const char* runs_columns_note();

// The time metrics of runs.csv: update_ms (slowest subdomain's forces plus integration, the
// paper's real time), update_ideal_ms (their mean), step_ms, then each phase's "<phase>_ms".
std::vector<std::string> time_metrics();
// Work counters compared exactly by `compare`.
const std::vector<std::string>& counter_columns();

}  // namespace sph
