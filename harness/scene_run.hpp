#pragma once
// One run of one scene: build it, step it, record every step, write what was asked for.
// Both `sphbench simulate` and the spec-driven `sphbench run` go through here; the steps are
// the run loop's (run_loop.hpp), with the stop rules and sinks that the request asks for.
#include <map>
#include <string>
#include <vector>

#include "gauge.hpp"
#include "provenance.hpp"
#include "run_cost_sink.hpp"
#include "simulation.hpp"
#include "step_table.hpp"
#include "validation_recorder.hpp"
#include "work_counter_sink.hpp"

namespace sph {

struct SceneRunRequest {
    std::string scene;
    std::map<std::string, std::string> scene_options;
    SolverOptions solver;
    long steps = 100;             // recorded steps; with an end time their cap, 0: no cap
    long warmup = 0;              // steps run first and not recorded
    double end_time = 0;          // > 0: stop at the first step whose simulated time reaches it (0: the validation's)
    long snapshot_every = 0;      // 0: no snapshots
    long count_work_every = 0;    // 0: work counters once, on the state the run ends with
    std::string out_dir;          // "" writes nothing
    std::string basename;         // file stem of this run's outputs
    bool write_step_csv = true;
    bool progress = true;
    bool calibrate_search = false;  // time every search strategy first and run the fastest
    Metadata metadata;            // provenance lines for every file
    ValidationRequest validation; // off unless asked for: the scene's metric at output times
    bool record_blow_up = false;  // a blow-up ends the run and is reported in the result, not thrown
    // Sampled into <basename>_gauges.csv (gauge_sink.hpp) with a case file's own gauges: the
    // case's first, one of these with a case gauge's name in its place, the others after
    // (merge_gauges); checked against the scene (exit 2 material) before the simulation is
    // built. Unnamed ones are named KIND<n>.
    std::vector<Gauge> gauges;
};

struct SceneRunResult {
    std::vector<StepRecord> steps;  // recorded (post warm-up) steps
    WorkTotals work;
    std::size_t particles = 0, fluid = 0, boundary = 0;
    std::size_t bytes_allocated = 0;
    double dp = 0;
    std::string device;
    // The whole run, from t = 0, warm-up included: what a user waits for.
    long steps_taken = 0;
    double sim_time = 0;      // simulated time reached
    double wall_seconds = 0;  // the run loop's wall clock: every step and the sinks' work between them
    double end_time = 0;      // as asked (0: none)
    std::string stopped_by;   // "end_time", "steps" (the step budget or cap) or "blow_up"
    RunCost cost;             // steps, and with Verlet lists the rebuild and listed steps
    std::size_t list_bytes = 0;  // the neighbour lists' memory (Verlet lists), all subdomains
    double seconds_per_sim_second() const { return sim_time > 0 ? wall_seconds / sim_time : 0; }
    std::vector<std::string> files;  // what was written
    std::map<std::string, std::string> scene_settings;
    std::string transport;  // multi-subdomain runs: the transport, and why when it fell back
    // MPI runs: how particles between ranks travelled ("host-memory", "staged-pinned"), and
    // why when that is not what was asked; "" in one process.
    std::string rank_transport;
    std::string search_choice;  // what calibration picked, with every trial's time
    std::vector<std::pair<std::string, double>> validation_summary;  // empty without validation
    std::string blow_up;  // with record_blow_up: what blew up, where; empty when the run finished
    double validation_seconds = 0;  // wall time spent on validation samples (inside wall_seconds)
};

// Throws InputError for bad input and RunError (BlowUpError) when the run fails; on a
// blow-up the last good state is written beside the other outputs first.
SceneRunResult run_scene(const SceneRunRequest& request);

}  // namespace sph
