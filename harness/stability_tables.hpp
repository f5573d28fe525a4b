#pragma once
// The tables of `sphbench stability`, each column declared once beside the value that fills
// it (column_table.hpp): summary.csv of a CFL-limit study and its trials.csv, summary.csv of
// an energy study and each run's <run_id>_energy.csv.
#include <string>

#include "column_table.hpp"
#include "energy_monitor.hpp"
#include "experiment_spec.hpp"
#include "stability_probe.hpp"

namespace sph {

// What every summary row starts with: what ran, where, at which size.
struct StudyRun {
    const PlannedRun& run;
    const Scene& scene;
    double target_time;
};

struct CflLimitRow {
    StudyRun at;
    const CflLimit& limit;
    const TrialOutcome* smallest_failure;  // nullptr: every trial was stable
    double wall_s;
};
const ColumnTable<CflLimitRow>& cfl_limit_table();

struct TrialRow {
    const std::string& run_id;
    const TrialOutcome& trial;
};
const ColumnTable<TrialRow>& trial_table();

struct EnergySampleRow {
    const EnergySample& sample;
    const EnergySample& initial;
    double scale;  // energy_scale(): what drifts are divided by
};
const ColumnTable<EnergySampleRow>& energy_series_table();

struct EnergySummaryRow {
    StudyRun at;
    const TrialOutcome& trial;
    double scale;
    const EnergySample &initial, &final;
    double largest_total_drift, largest_free_surface_drift;  // signed, largest in magnitude
    std::string series, last_good;                          // file names
};
const ColumnTable<EnergySummaryRow>& energy_summary_table();

}  // namespace sph
