#pragma once
// Experiment specs: one TOML file per figure or study, parsed strictly and expanded into runs.
//
//   name = "fig4"                      # required; results go to results/<name>/
//   reproduces = "Figure 4: ..."       # required; shown by `sphbench list`
//   description = "..."                # optional
//   steps = 1000                       # required; recorded steps per run (> 0); with end_time
//                                      #   optional: a cap on the steps after the warm-up
//   end_time = 1.0                     # optional; each run stops at the first step whose
//                                      #   simulated time reaches it (> 0; `steps` is then a cap)
//   warmup = 0                         # optional; steps run first and not recorded (>= 0)
//   repetitions = 1                    # optional; each repetition is its own run (row)
//   max_repetitions = 16               # optional; `run --baseline` adds repetitions up to this
//                                      #   many while a verdict against the baseline is inconclusive
//   seed = 1                           # optional; recorded in the provenance
//   record = ["summary", "steps"]      # optional; any of summary, steps, snapshots,
//                                      #   counters-every-step (runs.csv is always written)
//   snapshot_every = 0                 # HDF5 snapshot every K steps; needs "snapshots"
//   [solver]                           # optional defaults for every run; the keys, their
//                                      #   ranges and defaults are the table of solver_settings.cpp,
//                                      #   which makes the `simulate` flags too (--cells-per-support):
//     backend = "auto"                 #   "auto", "cuda" or "host"
//     devices = 1                      #   X-slab subdomains (1..1024), on N GPUs, one, or the host
//     gpu = 0                          #   GPU of a one-subdomain run (0..1023)
//     device_map = [0, 1]              #   GPU of each subdomain; absent: subdomain d on GPU d mod GPUs
//     share_gpus = false               #   MPI ranks of a node may share its GPUs
//     balancer = "none"                #   "none", "simple", "every:K", "threshold" or "equal-time[:F]"
//     transport = "auto"               #   "auto", "host", "peer", "staged" or "nccl"
//     gpu_direct = false               #   GPU memory to a CUDA-aware MPI (checked; staged so far)
//     cells_per_support = 1            #   1..4 (Smaller Cell)
//     merge = false                    #   Cell Merging
//     verlet = false                   #   Verlet lists
//     skin = 0.1                       #   Verlet skin, fraction of the support, (0, 1]
//     rebuild_every = 0                #   Verlet rebuild every k steps; 0: on displacement
//     fixed_dt = 1e-4                  #   (0, 1000] s: fixed step; absent: CFL-limited
//     cfl = 0.2                        #   (0, 1]; absent: the scene's
//     diffusion = true                 #   delta-SPH density diffusion
//     precision = "float32"            #   "float32" or "float64" (specs only: a build property)
//   [[runs]]                           # one or more
//     scene = "armadillo"              #   required; a scene of `sphbench info`, or "case:FILE" (case_file.hpp)
//     label = "armadillo-2980K"        #   optional; default: scene name and index
//     steps = 1000                     #   optional: this run's steps (replaces the top level's)
//     end_time = 0.3                   #   optional: this run's end time (replaces the top level's)
//     set = { particles = 2980000 }    #   scene options: integer, float or string values
//     solver = { merge = true }        #   optional per-run overrides of [solver]
//   [sweep]                            # optional cartesian product over every run: each key a
//     cells_per_support = [1, 2]       #   solver key or "set.<scene option>", each an array
//   blow_up = "fail"                   # optional: "fail" (the experiment stops) or "record" (the
//                                      #   run's row says where it blew up; the others go on)
//   [validation]                       # optional: the scene's metric (dambreak, tank) at output times
//     every = 0.02                     #   simulated seconds between output times (> 0, required)
//     end_time = 0.5                   #   optional: runs stop at this simulated time (steps: a cap)
//   (a [[runs]] entry may carry its own: validation = { every = ..., end_time = ... })
//   [[gauges]]                         # optional, any number; sampled in every run into
//     kind = "water_level"             #   <run>_gauges.csv: pressure, velocity (x, y, z),
//     name = "wg1"                     #   water_level (x, y), max_height (x, y, radius),
//     x = 0.6                          #   force (body = "tank"); every (s, > 0) required;
//     y = 0.335                        #   name optional (gauge_options.hpp); a case file's
//     every = 0.01                     #   gauge of the same name is replaced by this one, the
//                                      #   case's others are sampled too (case_file.hpp)
//   [host]                             # optional; when a run's backend resolves to the host:
//     scale = 0.01                     #   particle counts times this (dp over its cube root)
//     steps = 100                      #   replaces steps (with an end time: a cap)
//     end_time = 0.05                  #   replaces the end time of the runs that have one
//   [stability]                        # optional; makes the spec a study for `sphbench stability`
//     probe = "cfl-limit"              #   "cfl-limit" (bisection over cfl) or "energy" (time series)
//     time = 0.5                       #   simulated seconds a run must reach (absent: `steps` steps);
//                                      #   `steps` is then the most steps a run may take
//     cfl_low = 0.05                   #   cfl-limit: a bracket whose low end should be stable
//     cfl_high = 4.0                   #   ... and whose high end should not
//     bisections = 6                   #   cfl-limit: halvings of the bracket
//     sample_every = 100               #   energy: an energy and free-surface sample every K steps
//
// Anything else is refused with an InputError naming the file, the line and the key.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gauge.hpp"
#include "simulation.hpp"
#include "solver_settings.hpp"
#include "validation_recorder.hpp"

namespace sph {

struct RunSpec {
    std::string scene, label;
    SettingMap scene_options;  // set = { ... }
    SettingMap solver;         // per-run overrides
    std::optional<long> steps;        // replaces the spec's steps
    std::optional<double> end_time;   // replaces the spec's end_time
    std::optional<ValidationRequest> validation;  // replaces the spec's [validation]
    long line = 0;             // where the [[runs]] entry starts, for messages
};

struct SweepAxis {
    std::string key;  // a solver key or "set.<option>"
    std::vector<std::string> values;
};

struct HostReduction {
    double scale = 1.0;
    long steps = 0;         // 0: keep the spec's steps
    double end_time = 0;    // 0: keep the end times; else replaces them (in runs that have one)
};

struct StabilityStudy {
    std::string probe;  // "cfl-limit" or "energy"
    double time = 0;    // simulated time a run must reach; 0: run `steps` steps
    double cfl_low = 0.05, cfl_high = 4.0;
    long bisections = 6;
    long sample_every = 100;
};

struct ExperimentSpec {
    std::string path, name, reproduces, description;
    long steps = 0, warmup = 0, repetitions = 1, max_repetitions = 16;  // steps 0: no cap (only with an end time)
    double end_time = 0;                                                // 0: none
    long long seed = 1;
    std::vector<std::string> record = {"summary"};
    long snapshot_every = 0;
    SettingMap solver;
    std::vector<RunSpec> runs;
    std::vector<SweepAxis> sweep;  // ordered by key
    std::optional<HostReduction> host;
    std::optional<StabilityStudy> stability;  // only `sphbench stability` runs these
    std::optional<ValidationRequest> validation;
    bool record_blow_ups = false;  // blow_up = "record"
    std::vector<Gauge> gauges;     // [[gauges]]: sampled in every run (gauge_options.hpp); unnamed ones
                                   // are named in the run, after a case file's gauges (merge_gauges)

    bool records(const std::string& item) const;
};

// Throws InputError naming the file and line of any problem.
ExperimentSpec load_spec(const std::string& path);

struct ExpandOptions {
    std::vector<std::pair<std::string, std::string>> overrides;  // --set key=value, in order
    double scale = 1.0;                                          // --scale
    std::string backend;        // --backend: "" keeps the spec's choice
    bool gpu_available = false;  // how "auto" resolves
};

struct PlannedRun {
    std::string run_id;  // unique per row, filename-safe: config plus "_rep<k>" when repeated
    std::string config;  // label plus sweep values: what compare matches across repetitions
    std::string label, scene;
    SettingMap scene_options;    // after scaling
    SettingMap solver_settings;  // every solver key, resolved, for CSV columns
    SolverOptions solver;
    long steps = 0, warmup = 0, snapshot_every = 0;  // steps: recorded steps, or their cap; 0: no cap
    double end_time = 0;  // > 0: the run stops at the first step that reaches it
    long repetition = 1;  // 1-based
    double scale = 1.0;   // --scale times [host] scale where it applied
    bool reduced_scale = false;
    ValidationRequest validation;  // off unless the spec asks
    bool record_blow_up = false;   // the spec's blow_up = "record"
};

// The cartesian product of runs x sweep x repetitions with overrides and scaling applied.
// Throws InputError for an override of an unknown key or a bad value.
std::vector<PlannedRun> expand(const ExperimentSpec& spec, const ExpandOptions& options);

// FNV-1a 64 of the file's bytes, as 16 hex digits. Throws InputError if unreadable.
std::string spec_hash(const std::string& path);
std::string fnv1a_hex(const std::string& bytes);

}  // namespace sph
