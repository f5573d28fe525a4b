#pragma once
// Regression verdicts between two sets of results. A result set is an experiment folder
// (runs.csv plus its per-step CSVs) or a Google Benchmark JSON file. Runs are matched by
// their configuration (runs.csv's `config`, which is run_id less the repetition; run_id
// where there is no such column; the benchmark name for JSON).
//
// Time metrics: samples are the per-step values where both sides have step files, else the
// per-repetition medians. The verdict comes from the relative change of the medians and,
// where both sides have at least 8 samples, a two-sided Mann-Whitney U test:
//   SAME       |change| < threshold
//   SLOWER     change > +threshold and p < alpha      (a regression)
//   FASTER     change < -threshold and p < alpha
//   AMBIGUOUS  beyond the threshold but not significant, or too few samples to tell
// Work counters are deterministic and compared exactly: any difference is COUNTER CHANGED,
// which is a regression too.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace sph {

struct RunSamples {
    std::map<std::string, std::vector<double>> step_values;  // metric -> per-step values, all repetitions
    std::map<std::string, std::vector<double>> run_values;   // metric -> one median per repetition
    std::map<std::string, std::string> counters;             // counter -> value (first repetition)
    bool all_steps_files = true;                             // every repetition had a step file
};

struct ResultSet {
    std::string source;
    std::map<std::string, RunSamples> runs;  // by configuration
};

// A folder (or its runs.csv) or a Google Benchmark JSON file. Throws InputError when it is
// missing or unreadable.
ResultSet load_results(const std::string& path);
ResultSet load_benchmark_json(const std::string& path);  // in benchmark_json.cpp

enum class Verdict { same, faster, slower, ambiguous, counter_changed };
const char* verdict_name(Verdict v);

struct CompareOptions {
    double threshold = 0.05;  // minimum relative change of the median that counts
    double alpha = 0.01;      // significance level of the rank test
    std::vector<std::string> time_metrics = {"update_ms", "step_ms"};  // empty: counters only
    static constexpr std::size_t min_samples = 8;  // for the rank test
};

struct MetricComparison {
    std::string run, metric;
    bool counter = false;
    std::string baseline_text, candidate_text;  // counters: the values as written
    double baseline = 0, candidate = 0;         // times: the medians
    double change = 0;                          // relative change of the medians
    double p = -1;                              // rank test p-value; < 0 where not computed
    std::size_t n_baseline = 0, n_candidate = 0;
    Verdict verdict = Verdict::same;
};

struct Comparison {
    std::vector<MetricComparison> rows;
    std::vector<std::string> only_in_baseline, only_in_candidate;
    bool regressed() const;
    bool comparable() const { return !rows.empty(); }
};

Comparison compare_results(const ResultSet& baseline, const ResultSet& candidate, const CompareOptions& options);

// 0 nothing regressed, 1 a regression (SLOWER or COUNTER CHANGED), 3 nothing comparable.
int comparison_exit_code(const Comparison& c);

// Two-sided p-value of the Mann-Whitney U test, normal approximation with tie correction
// and continuity correction.
double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b);

Verdict time_verdict(double change, double p, bool enough_samples, const CompareOptions& options);

}  // namespace sph
