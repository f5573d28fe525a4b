#pragma once
// The start that `sphbench run` and `sphbench stability` share: load the spec, check the
// output folder, expand it with the command line's overrides, write the provenance of its
// tables, and skip it when its results are up to date (result_freshness.hpp).
#include <string>
#include <vector>

#include "commands.hpp"
#include "experiment_spec.hpp"
#include "provenance.hpp"

namespace sph {

// What the command line says about an experiment, the same for both commands.
struct ExperimentArgs {
    std::string spec;
    std::vector<std::string> settings;  // --set key=value
    double scale = 1.0;
    std::string backend;
    std::string out = "results";
    std::vector<std::string> only;  // run ids to run (`run` only)
    bool force = false;
};

// `run` takes specs without a [stability] table, `stability` specs with one.
enum class ExperimentKind { runs, stability };

struct Experiment {
    ExperimentSpec spec;
    std::vector<PlannedRun> runs;  // expanded, overridden, filtered by --only
    std::string dir;               // <out>/<name>
    bool reduced = false;          // a run at a reduced scale (or step count)
    std::string backend;           // "cuda", "host" or "mixed"
};

// `--end-time T` on `run` and `stability`: the same as `--set end_time=T` (checked as the spec
// key is), so that it travels with the other overrides.
void add_end_time_option(CLI::App& cmd, ExperimentArgs& args, const std::string& help);

// Throws InputError, before any work starts, for a bad spec, an output folder that cannot be
// one, a spec of the other kind, a bad override or an --only naming no run.
Experiment load_experiment(const ExperimentArgs& args, ExperimentKind kind);

// The overrides as arguments for another sphbench ("--set", "k=v", "--scale", "2", ...),
// without --only.
std::vector<std::string> override_arguments(const ExperimentArgs& args);
// Every override in one line ("--set k=v --only id"), "none" without: part of what makes
// results up to date.
std::string overrides_text(const ExperimentArgs& args);

// The provenance of every table: build, backend, devices, date, command line, then the
// experiment's experiment, reproduces, spec, spec_hash, case_hashes, binary_hash, overrides, seed, scale
// and reduced_scale. A command appends its own keys after these.
Metadata experiment_metadata(const Experiment& e, const ExperimentArgs& args, const CommandContext& ctx);

// True, after saying so, when `table` is up to date with `metadata` and --force was not given.
bool skip_up_to_date(const Experiment& e, const ExperimentArgs& args, const std::string& table,
                     const Metadata& metadata);

}  // namespace sph
