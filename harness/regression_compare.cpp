#include "regression_compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "core/error.hpp"
#include "csv_table.hpp"
#include "experiment_runner.hpp"
#include "statistics.hpp"

namespace sph {
namespace {

namespace fs = std::filesystem;

double to_double(const std::string& text, const std::string& where) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0') throw InputError(where + ": '" + text + "' is not a number");
    return v;
}

ResultSet load_folder(const fs::path& runs_csv) {
    const CsvTable t = read_csv(runs_csv.string());
    if (t.column("run_id") < 0) throw InputError("'" + runs_csv.string() + "' has no run_id column");
    ResultSet set;
    set.source = runs_csv.parent_path().string();
    const std::string key_column = t.column("config") >= 0 ? "config" : "run_id";
    std::map<std::string, long> first_repetition;
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
        const std::string key = t.cell(i, key_column);
        RunSamples& run = set.runs[key];
        const std::string where = runs_csv.string() + " run '" + t.cell(i, "run_id") + "'";
        for (const auto& m : time_metrics()) {
            const std::string& v = t.cell(i, m + "_median");
            if (!v.empty()) run.run_values[m].push_back(to_double(v, where));
        }
        const std::string& steps_file = t.cell(i, "steps_file");
        if (steps_file.empty()) {
            run.all_steps_files = false;
        } else {
            const CsvTable steps = read_csv((runs_csv.parent_path() / steps_file).string());
            for (const auto& m : time_metrics()) {
                const int c = steps.column(m);
                if (c < 0) continue;
                for (const auto& row : steps.rows) run.step_values[m].push_back(to_double(row[std::size_t(c)], steps.path));
            }
        }
        const std::string& rep_text = t.cell(i, "repetition");
        const long rep = rep_text.empty() ? 1 : std::atol(rep_text.c_str());
        auto [it, fresh] = first_repetition.emplace(key, rep);
        if (fresh || rep < it->second) {
            it->second = rep;
            for (const auto& c : counter_columns())
                if (t.column(c) >= 0) run.counters[c] = t.cell(i, c);
        }
    }
    return set;
}

double median_of(const std::vector<double>& v) { return summarize(v).median; }

constexpr std::size_t min_split_group = 2;  // repetitions on each side of a split: one is an outlier

// In sorted values, the index of the first value above the widest gap that leaves at least
// min_split_group values on each side; 0 when there are too few values.
std::size_t widest_gap(const std::vector<double>& sorted) {
    std::size_t at = 0;
    for (std::size_t k = min_split_group; k + min_split_group <= sorted.size(); ++k)
        if (at == 0 || sorted[k] - sorted[k - 1] > sorted[at] - sorted[at - 1]) at = k;
    return at;
}

// Counters are written by one formatter, but compare numerically so "2" equals "2.0".
bool same_counter(const std::string& a, const std::string& b) {
    if (a == b) return true;
    char *ea = nullptr, *eb = nullptr;
    const double x = std::strtod(a.c_str(), &ea), y = std::strtod(b.c_str(), &eb);
    return !a.empty() && !b.empty() && *ea == '\0' && *eb == '\0' && x == y;
}

}  // namespace

ResultSet load_results(const std::string& path) {
    const fs::path p(path);
    if (fs::is_directory(p)) {
        if (!fs::exists(p / "runs.csv")) throw InputError("result folder '" + path + "' has no runs.csv");
        return load_folder(p / "runs.csv");
    }
    if (!fs::exists(p)) throw InputError("'" + path + "' does not exist");
    if (p.extension() == ".json") return load_benchmark_json(path);
    if (p.extension() == ".csv") return load_folder(p);
    throw InputError("'" + path + "' is neither a result folder, a runs.csv nor a Google Benchmark .json file");
}

const char* verdict_name(Verdict v) {
    switch (v) {
    case Verdict::same: return "SAME";
    case Verdict::faster: return "FASTER";
    case Verdict::slower: return "SLOWER";
    case Verdict::ambiguous: return "AMBIGUOUS";
    case Verdict::noisy: return "NOISY";
    case Verdict::counter_changed: return "COUNTER CHANGED";
    }
    return "?";
}

bool Comparison::regressed() const {
    return std::any_of(rows.begin(), rows.end(), [](const MetricComparison& m) {
        return m.verdict == Verdict::slower || m.verdict == Verdict::counter_changed;
    });
}

bool Comparison::inconclusive() const {
    return std::any_of(rows.begin(), rows.end(), [](const MetricComparison& m) {
        return m.verdict == Verdict::ambiguous || m.verdict == Verdict::noisy;
    });
}

int comparison_exit_code(const Comparison& c) {
    if (!c.comparable()) return 3;
    if (c.regressed()) return 1;
    return c.inconclusive() ? exit_inconclusive : 0;
}

const char* overall_verdict(const Comparison& c) {
    switch (comparison_exit_code(c)) {
    case 0: return "NO REGRESSION";
    case 1: return "REGRESSION";
    case 3: return "NOTHING COMPARABLE";
    default: return "INCONCLUSIVE";
    }
}

std::string inconclusive_advice(const Comparison& c) {
    const bool noisy = std::any_of(c.rows.begin(), c.rows.end(), [](const MetricComparison& r) { return r.verdict == Verdict::noisy; });
    std::string s = "inconclusive: rerun the candidate with more repetitions (--set repetitions=N";
    s += ", or `sphbench run SPEC --baseline DIR`, which adds repetitions while a verdict is AMBIGUOUS)";
    if (noisy) s += " on a quiet machine (nothing else running on its cores)";
    s += ", then compare again";
    const auto thin = std::find_if(c.rows.begin(), c.rows.end(), [](const MetricComparison& r) {
        return r.verdict == Verdict::ambiguous && r.n_baseline < CompareOptions::min_samples;
    });
    if (thin != c.rows.end())
        s += "; rerun the baseline too: it has " + std::to_string(thin->n_baseline) + " sample(s) of " + thin->run + " " +
             thin->metric + " where the rank test needs " + std::to_string(CompareOptions::min_samples);
    if (std::any_of(c.rows.begin(), c.rows.end(), [](const MetricComparison& r) { return r.disturbance.in_baseline; }))
        s += "; rerun the baseline too: its repetitions disagree";
    if (!c.regressed()) s += "; exit " + std::to_string(exit_inconclusive);
    return s;
}

Disturbance find_disturbance(const std::vector<double>& base, const std::vector<double>& cand,
                             const std::vector<double>& base_reps, const std::vector<double>& cand_reps,
                             double change, const CompareOptions& o) {
    Disturbance d;
    const auto relative_iqr = [](const std::vector<double>& v) {
        const Summary s = summarize(v);
        return s.median != 0 ? (s.q3 - s.q1) / std::abs(s.median) : 0.0;
    };
    char buf[256];
    if (base.size() >= CompareOptions::min_spread_samples && cand.size() >= CompareOptions::min_spread_samples) {
        d.spread_baseline = relative_iqr(base);
        d.spread_candidate = relative_iqr(cand);
        if (d.spread_candidate >= o.threshold && d.spread_candidate >= o.noise_ratio * d.spread_baseline) {
            d.found = true;
            std::snprintf(buf, sizeof buf,
                          "the candidate is far noisier than the baseline: its interquartile range is %.1f%% of its "
                          "median against the baseline's %.1f%%",
                          100 * d.spread_candidate, 100 * d.spread_baseline);
            d.why = buf;
        }
    }
    if (!base_reps.empty() && cand_reps.size() >= 2 * min_split_group) {
        std::vector<double> c = cand_reps, b = base_reps;
        std::sort(c.begin(), c.end());
        std::sort(b.begin(), b.end());
        const Summary bs = summarize(b);
        const std::size_t at = widest_gap(c), base_at = widest_gap(b);
        const double gap = c[at] - c[at - 1];
        // The baseline's own scatter: its quartiles, or a split of its own (a bimodal machine).
        const double base_scatter = std::max(bs.q3 - bs.q1, base_at ? b[base_at] - b[base_at - 1] : 0.0);
        if (gap >= o.threshold * std::abs(bs.median) && gap > o.noise_ratio * base_scatter) {
            d.found = true;
            d.fast_group = at;
            d.slow_group = c.size() - at;
            d.fast_median = summarize(std::vector<double>(c.begin(), c.begin() + long(at))).median;
            d.slow_median = summarize(std::vector<double>(c.begin() + long(at), c.end())).median;
            std::snprintf(buf, sizeof buf,
                          "the candidate's repetitions split into %zu near %.4g and %zu near %.4g (the baseline's "
                          "median: %.4g)",
                          d.fast_group, d.fast_median, d.slow_group, d.slow_median, bs.median);
            d.why += (d.why.empty() ? "" : "; ") + std::string(buf);
        }
    }
    const auto scatter = [&](const std::vector<double>& reps, double& out, const char* side) {
        if (reps.size() < CompareOptions::min_scatter_repetitions) return false;
        out = relative_iqr(reps);
        if (out >= o.threshold && o.noise_ratio * out >= std::abs(change)) {
            d.found = true;
            std::snprintf(buf, sizeof buf,
                          "the %s's %zu repetitions disagree: their medians' interquartile range is %.1f%% of their "
                          "median, against a change of %+.1f%%",
                          side, reps.size(), 100 * out, 100 * change);
            d.why += (d.why.empty() ? "" : "; ") + std::string(buf);
            return true;
        }
        return false;
    };
    d.in_baseline = scatter(base_reps, d.scatter_baseline, "baseline");
    scatter(cand_reps, d.scatter_candidate, "candidate");
    return d;
}

double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b) {
    const std::size_t n1 = a.size(), n2 = b.size(), n = n1 + n2;
    if (n1 == 0 || n2 == 0) return 1.0;
    std::vector<std::pair<double, int>> all;  // value, 0 for a and 1 for b
    all.reserve(n);
    for (double v : a) all.emplace_back(v, 0);
    for (double v : b) all.emplace_back(v, 1);
    std::sort(all.begin(), all.end());
    double rank_sum_a = 0, tie_term = 0;
    for (std::size_t i = 0; i < n;) {
        std::size_t j = i;
        while (j < n && all[j].first == all[i].first) ++j;
        const double average_rank = 0.5 * double(i + 1 + j);  // ranks i+1 .. j
        for (std::size_t k = i; k < j; ++k)
            if (all[k].second == 0) rank_sum_a += average_rank;
        const double t = double(j - i);
        tie_term += t * t * t - t;
        i = j;
    }
    const double u = rank_sum_a - double(n1) * double(n1 + 1) / 2;
    const double mean = double(n1) * double(n2) / 2;
    const double variance =
        double(n1) * double(n2) / 12.0 * (double(n + 1) - tie_term / (double(n) * double(n - 1)));
    if (variance <= 0) return 1.0;  // every value tied
    const double diff = std::abs(u - mean);
    const double z = std::max(0.0, diff - 0.5) / std::sqrt(variance);
    return std::erfc(z / std::sqrt(2.0));
}

Verdict time_verdict(double change, double p, bool enough_samples, const CompareOptions& o) {
    if (std::abs(change) < o.threshold) return Verdict::same;
    if (!enough_samples || !(p < o.alpha)) return Verdict::ambiguous;
    return change > 0 ? Verdict::slower : Verdict::faster;
}

Comparison compare_results(const ResultSet& base, const ResultSet& cand, const CompareOptions& o) {
    Comparison out;
    for (const auto& [id, b] : base.runs)
        if (!cand.runs.count(id)) out.only_in_baseline.push_back(id);
    for (const auto& [id, c] : cand.runs)
        if (!base.runs.count(id)) out.only_in_candidate.push_back(id);

    std::vector<std::string> metrics = o.time_metrics;
    if (!metrics.empty()) metrics.push_back("real_time");  // what Google Benchmark files hold
    for (const auto& [id, b] : base.runs) {
        const auto found = cand.runs.find(id);
        if (found == cand.runs.end()) continue;
        const RunSamples& c = found->second;
        for (const auto& m : metrics) {
            const bool per_step = b.all_steps_files && c.all_steps_files && b.step_values.count(m) &&
                                  c.step_values.count(m) && !b.step_values.at(m).empty() &&
                                  !c.step_values.at(m).empty();
            const auto& bs = per_step ? b.step_values : b.run_values;
            const auto& cs = per_step ? c.step_values : c.run_values;
            if (!bs.count(m) || !cs.count(m) || bs.at(m).empty() || cs.at(m).empty()) continue;
            MetricComparison r;
            r.run = id;
            r.metric = m;
            r.n_baseline = bs.at(m).size();
            r.n_candidate = cs.at(m).size();
            r.baseline = median_of(bs.at(m));
            r.candidate = median_of(cs.at(m));
            if (r.baseline != 0) r.change = (r.candidate - r.baseline) / r.baseline;
            else r.change = r.candidate == 0 ? 0 : std::copysign(std::numeric_limits<double>::infinity(), r.candidate);
            const bool enough = r.n_baseline >= CompareOptions::min_samples && r.n_candidate >= CompareOptions::min_samples;
            if (enough) r.p = mann_whitney_p(bs.at(m), cs.at(m));
            r.verdict = time_verdict(r.change, r.p, enough, o);
            static const std::vector<double> none;
            const auto reps = [&m](const RunSamples& s) -> const std::vector<double>& {
                const auto it = s.run_values.find(m);
                return it == s.run_values.end() ? none : it->second;
            };
            r.disturbance = find_disturbance(bs.at(m), cs.at(m), reps(b), reps(c), r.change, o);
            if (r.disturbance.found) r.verdict = Verdict::noisy;
            out.rows.push_back(r);
        }
        for (const auto& counter : counter_columns()) {
            const auto bi = b.counters.find(counter), ci = c.counters.find(counter);
            if (bi == b.counters.end() || ci == c.counters.end()) continue;
            if (bi->second.empty() && ci->second.empty()) continue;  // counted by neither
            MetricComparison r;
            r.run = id;
            r.metric = counter;
            r.counter = true;
            r.baseline_text = bi->second;
            r.candidate_text = ci->second;
            r.n_baseline = r.n_candidate = 1;
            const double x = std::strtod(bi->second.c_str(), nullptr), y = std::strtod(ci->second.c_str(), nullptr);
            r.baseline = x;
            r.candidate = y;
            r.change = x != 0 ? (y - x) / x : (y == 0 ? 0 : std::numeric_limits<double>::infinity());
            r.verdict = same_counter(bi->second, ci->second) ? Verdict::same : Verdict::counter_changed;
            out.rows.push_back(r);
        }
    }
    return out;
}

}  // namespace sph
