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
//   NOISY      whatever the change, signs of a machine disturbed while a side ran (see
//              find_disturbance): the candidate far noisier than the baseline, its
//              repetitions split in two groups, or one side's repetitions disagreeing
// AMBIGUOUS and NOISY are inconclusive: the comparison does not know, and says so by its exit
// code. Work counters are deterministic and compared exactly: any difference is COUNTER
// CHANGED, which is a regression too.
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

enum class Verdict { same, faster, slower, ambiguous, noisy, counter_changed };
const char* verdict_name(Verdict v);

struct CompareOptions {
    double threshold = 0.05;  // minimum relative change of the median that counts
    double alpha = 0.01;      // significance level of the rank test
    double noise_ratio = 3;   // a candidate this many times as spread as its baseline is NOISY
    std::vector<std::string> time_metrics = {"update_ms", "step_ms"};  // empty: counters only
    static constexpr std::size_t min_samples = 8;         // for the rank test
    static constexpr std::size_t min_spread_samples = 8;  // for a spread (interquartile range)
    static constexpr std::size_t min_scatter_repetitions = 4;  // for the repetitions' scatter
};

// Signs that timings were disturbed (other processes on the machine), from the samples the
// verdict uses and the per-repetition medians. Timings of one build on a quiet machine are
// unimodal, about as spread as its baseline's, and its repetitions agree; load makes some or
// all of them slower, so that the candidate is far more spread, its repetitions fall into two
// groups, or the repetitions of either side disagree.
//   spread: the candidate's interquartile range relative to its median is at least
//           noise_ratio times the baseline's and at least the threshold (spread that small
//           cannot hide a change that counts);
//   split:  sorted, the candidate's repetition medians have a gap, with at least two
//           repetitions on each side (one is an outlier), of at least the threshold (relative
//           to the baseline's median) and more than noise_ratio times the baseline
//           repetitions' scatter (their interquartile range, or their own widest such gap):
//           some repetitions ran at one speed and the others at another;
//   scatter: the repetition medians of either side (at least min_scatter_repetitions) have
//           an interquartile range, relative to their median, of at least the threshold and
//           at least 1/noise_ratio of the change: one build's repetitions disagree by as much
//           as the change that counts and the change measured. This also catches pooled
//           per-step samples that make a rank test overconfident: steps of one repetition
//           share the machine's state.
struct Disturbance {
    bool found = false;
    bool in_baseline = false;                            // the baseline's repetitions disagree
    double spread_baseline = -1, spread_candidate = -1;  // relative IQR; < 0 where too few samples
    double scatter_baseline = -1, scatter_candidate = -1;  // the repetitions' relative IQR; likewise
    std::size_t fast_group = 0, slow_group = 0;          // repetitions below and above the split
    double fast_median = 0, slow_median = 0;             // their medians
    std::string why;                                     // clauses for the report; empty if none
};
Disturbance find_disturbance(const std::vector<double>& baseline_samples, const std::vector<double>& candidate_samples,
                             const std::vector<double>& baseline_repetitions,
                             const std::vector<double>& candidate_repetitions, double change,
                             const CompareOptions& options);

struct MetricComparison {
    std::string run, metric;
    bool counter = false;
    std::string baseline_text, candidate_text;  // counters: the values as written
    double baseline = 0, candidate = 0;         // times: the medians
    double change = 0;                          // relative change of the medians
    double p = -1;                              // rank test p-value; < 0 where not computed
    std::size_t n_baseline = 0, n_candidate = 0;
    Disturbance disturbance;                    // times only
    Verdict verdict = Verdict::same;
};

struct Comparison {
    std::vector<MetricComparison> rows;
    std::vector<std::string> only_in_baseline, only_in_candidate;
    bool regressed() const;
    bool inconclusive() const;  // some row is AMBIGUOUS or NOISY
    bool comparable() const { return !rows.empty(); }
};

Comparison compare_results(const ResultSet& baseline, const ResultSet& candidate, const CompareOptions& options);

// 0 nothing regressed and every verdict is known, 1 a regression (SLOWER or COUNTER CHANGED),
// 3 nothing comparable, 4 inconclusive (no regression, but some row is AMBIGUOUS or NOISY).
// A regression wins over an inconclusive row: it is known.
constexpr int exit_inconclusive = 4;
int comparison_exit_code(const Comparison& c);
// What to do about AMBIGUOUS or NOISY rows, one sentence starting "inconclusive:".
std::string inconclusive_advice(const Comparison& c);
// "REGRESSION", "INCONCLUSIVE", "NO REGRESSION" or "NOTHING COMPARABLE", as the exit code says.
const char* overall_verdict(const Comparison& c);

// Two-sided p-value of the Mann-Whitney U test, normal approximation with tie correction
// and continuity correction.
double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b);

Verdict time_verdict(double change, double p, bool enough_samples, const CompareOptions& options);

}  // namespace sph
