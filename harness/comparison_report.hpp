#pragma once
// The report of a comparison on standard output, the same for `compare` and `run --baseline`:
// the table of verdicts, the runs only one side has, why a candidate looks disturbed, the
// overall verdict with its tally and, where it is inconclusive, what to do.
#include <string>

#include "regression_compare.hpp"

namespace sph {

void print_comparison(const Comparison& c, const CompareOptions& options, const std::string& baseline,
                      const std::string& candidate);

}  // namespace sph
