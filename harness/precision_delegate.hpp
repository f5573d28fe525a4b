#pragma once
// Runs of the other floating-point precision. Precision is a build property (SPH_DOUBLE), so a
// float32 sphbench hands the runs that ask for `precision = "float64"` to a float64 build of
// itself, named explicitly (--float64-binary; `make accuracy` builds build-f64/). The child
// runs exactly those runs (`run SPEC --only ID ...`) into <experiment>/float64/, and its rows
// join runs.csv with their file columns pointing there.
#include <map>
#include <string>
#include <vector>

#include "experiment_spec.hpp"

namespace sph {

struct DelegatedRuns {
    std::string binary;                 // the float64 sphbench
    std::vector<std::string> run_ids;   // runs it is to run
    std::vector<std::string> arguments;  // the parent's --set, --scale and --backend, passed on
};

// The runs whose precision is not this build's. Throws InputError naming the first one when
// there is no binary to hand them to (or when they ask for float32 of a float64 build).
DelegatedRuns plan_delegation(const std::vector<PlannedRun>& runs, const std::string& float64_binary);

// Runs the child and returns its rows keyed by run id, with runs.csv's `columns` (cells the
// child did not write are empty). Throws RunError when the child fails or misses a run.
std::map<std::string, std::vector<std::string>> run_delegated(const DelegatedRuns& d, const ExperimentSpec& spec,
                                                              const std::string& experiment_dir,
                                                              const std::vector<std::string>& columns, bool quiet);

}  // namespace sph
