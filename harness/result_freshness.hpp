#pragma once
// Whether an experiment's results are up to date: one comparison for `run` and `stability`,
// so that both look at the same provenance keys.
#include <string>

#include "provenance.hpp"

namespace sph {

// True when `csv` exists, its metadata reads, and it agrees with `now` on the spec's hash, the
// hashes of the case files its runs are built from, the binary's (and the float64 binary's,
// where runs were handed to one), the command line's overrides and the backend. A key absent
// from both counts as agreeing.
bool results_up_to_date(const std::string& csv, const Metadata& now);

}  // namespace sph
