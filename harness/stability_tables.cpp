#include "stability_tables.hpp"

#include "io/csv_writer.hpp"

namespace sph {
namespace {

std::string f(double v) { return CsvWriter::fmt(v); }
std::string yes_no(bool b) { return b ? "true" : "false"; }

ColumnTable<StudyRun> study_run_table() {
    using R = const StudyRun&;
    ColumnTable<StudyRun> t;
    t.add("run_id", [](R r) { return r.run.run_id; })
        .add("scene", [](R r) { return r.run.scene; })
        .add("backend", [](R r) { return std::string(r.run.solver.backend == BackendKind::cuda ? "cuda" : "host"); })
        .add("particles", [](R r) { return std::to_string(r.scene.size()); })
        .add("fluid", [](R r) { return std::to_string(r.scene.fluid_count()); })
        .add("boundary", [](R r) { return std::to_string(r.scene.n_boundary); })
        .add("dp", [](R r) { return f(r.scene.dp); })
        .add("target_time", [](R r) { return f(r.target_time); })
        .add("max_steps", [](R r) { return std::to_string(r.run.steps); });
    return t;
}

ColumnTable<CflLimitRow> make_cfl_limit_table() {
    using R = const CflLimitRow&;
    ColumnTable<CflLimitRow> t;
    t.append(study_run_table(), [](R r) { return r.at; })
        .add("cfl_stable", [](R r) { return f(r.limit.stable); })
        .add("cfl_unstable", [](R r) { return f(r.limit.unstable); })
        .add("trials", [](R r) { return std::to_string(r.limit.trials.size()); })
        .add("unstable_failed_step",
             [](R r) { return r.smallest_failure ? std::to_string(r.smallest_failure->failed_step) : ""; })
        .add("unstable_quantity", [](R r) { return r.smallest_failure ? r.smallest_failure->quantity : ""; })
        .add("unstable_particle",
             [](R r) { return r.smallest_failure ? std::to_string(r.smallest_failure->particle) : ""; })
        .add("unstable_message", [](R r) { return r.smallest_failure ? r.smallest_failure->message : ""; })
        .add("wall_s", [](R r) { return f(r.wall_s); });
    return t;
}

// What one trial ended as: the columns the trial table and the energy summary share.
ColumnTable<TrialOutcome> trial_outcome_table() {
    using R = const TrialOutcome&;
    ColumnTable<TrialOutcome> t;
    t.add("cfl", [](R r) { return f(r.cfl); })
        .add("stable", [](R r) { return yes_no(r.stable); })
        .add("steps", [](R r) { return std::to_string(r.steps); })
        .add("time", [](R r) { return f(r.time); })
        .add("failed_step", [](R r) { return std::to_string(r.failed_step); })
        .add("particle", [](R r) { return r.stable ? "" : std::to_string(r.particle); })
        .add("quantity", [](R r) { return r.quantity; });
    return t;
}

ColumnTable<TrialRow> make_trial_table() {
    using R = const TrialRow&;
    ColumnTable<TrialRow> t;
    t.add("run_id", [](R r) { return r.run_id; })
        .append(trial_outcome_table(), [](R r) -> const TrialOutcome& { return r.trial; })
        .add("wall_s", [](R r) { return f(r.trial.wall_s); });
    return t;
}

ColumnTable<EnergySampleRow> make_energy_series_table() {
    using R = const EnergySampleRow&;
    ColumnTable<EnergySampleRow> t;
    t.add("step", [](R r) { return std::to_string(r.sample.step); })
        .add("time", [](R r) { return f(r.sample.time); })
        .add("kinetic", [](R r) { return f(r.sample.kinetic); })
        .add("potential", [](R r) { return f(r.sample.potential); })
        .add("internal_fluid", [](R r) { return f(r.sample.internal_fluid); })
        .add("internal_boundary", [](R r) { return f(r.sample.internal_boundary); })
        .add("total", [](R r) { return f(r.sample.total()); })
        .add("total_drift", [](R r) { return f((r.sample.total() - r.initial.total()) / r.scale); })
        .add("free_surface", [](R r) { return f(r.sample.free_surface); })
        .add("free_surface_drift", [](R r) { return f(r.sample.free_surface - r.initial.free_surface); })
        .add("fluid", [](R r) { return std::to_string(r.sample.fluid); });
    return t;
}

ColumnTable<EnergySummaryRow> make_energy_summary_table() {
    using R = const EnergySummaryRow&;
    ColumnTable<EnergySummaryRow> t;
    t.append(study_run_table(), [](R r) { return r.at; })
        .append(trial_outcome_table(), [](R r) -> const TrialOutcome& { return r.trial; })
        .add("energy_scale", [](R r) { return f(r.scale); })
        .add("total_drift", [](R r) { return f((r.final.total() - r.initial.total()) / r.scale); })
        .add("mechanical_drift", [](R r) { return f((r.final.mechanical() - r.initial.mechanical()) / r.scale); })
        .add("largest_total_drift", [](R r) { return f(r.largest_total_drift); })
        .add("free_surface_0", [](R r) { return f(r.initial.free_surface); })
        .add("free_surface_drift", [](R r) { return f(r.final.free_surface - r.initial.free_surface); })
        .add("largest_free_surface_drift", [](R r) { return f(r.largest_free_surface_drift); })
        .add("wall_s", [](R r) { return f(r.trial.wall_s); })
        .add("series", [](R r) { return r.series; })
        .add("last_good", [](R r) { return r.last_good; });
    return t;
}

}  // namespace

const ColumnTable<CflLimitRow>& cfl_limit_table() {
    static const ColumnTable<CflLimitRow> t = make_cfl_limit_table();
    return t;
}
const ColumnTable<TrialRow>& trial_table() {
    static const ColumnTable<TrialRow> t = make_trial_table();
    return t;
}
const ColumnTable<EnergySampleRow>& energy_series_table() {
    static const ColumnTable<EnergySampleRow> t = make_energy_series_table();
    return t;
}
const ColumnTable<EnergySummaryRow>& energy_summary_table() {
    static const ColumnTable<EnergySummaryRow> t = make_energy_summary_table();
    return t;
}

}  // namespace sph
