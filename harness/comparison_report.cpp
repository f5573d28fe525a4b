#include "comparison_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

namespace sph {
namespace {

std::string value_text(const MetricComparison& r, bool candidate) {
    if (r.counter) return candidate ? r.candidate_text : r.baseline_text;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", candidate ? r.candidate : r.baseline);
    return buf;
}

std::string change_text(const MetricComparison& r) {
    if (!std::isfinite(r.change)) return r.change > 0 ? "+inf" : "-inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%+.1f%%", 100 * r.change);
    return buf;
}

std::string p_text(const MetricComparison& r) {
    if (r.p < 0) return "-";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2g", r.p);
    return buf;
}

void print_table(const Comparison& c) {
    std::vector<std::vector<std::string>> rows = {{"run", "metric", "baseline", "candidate", "change", "p", "verdict"}};
    for (const auto& r : c.rows)
        rows.push_back({r.run, r.metric, value_text(r, false), value_text(r, true), change_text(r), p_text(r),
                        verdict_name(r.verdict)});
    std::vector<std::size_t> width(rows.front().size(), 0);
    for (const auto& row : rows)
        for (std::size_t i = 0; i < row.size(); ++i) width[i] = std::max(width[i], row[i].size());
    for (const auto& row : rows) {
        std::string line;
        for (std::size_t i = 0; i < row.size(); ++i) {
            const bool numeric = i >= 2 && i <= 5;  // right-aligned
            const std::string pad(width[i] - row[i].size(), ' ');
            line += (i ? "  " : "") + (numeric ? pad + row[i] : row[i] + (i + 1 < row.size() ? pad : ""));
        }
        std::printf("%s\n", line.c_str());
    }
}

}  // namespace

void print_comparison(const Comparison& c, const CompareOptions& options, const std::string& baseline,
                      const std::string& candidate) {
    if (c.comparable()) print_table(c);
    for (const auto& id : c.only_in_baseline) std::printf("only in the baseline: %s\n", id.c_str());
    for (const auto& id : c.only_in_candidate) std::printf("only in the candidate: %s\n", id.c_str());
    std::map<std::string, int> tally;
    for (const auto& r : c.rows) ++tally[verdict_name(r.verdict)];
    std::string counts;
    for (const auto& [name, n] : tally) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + name;
    for (const auto& r : c.rows)
        if (r.disturbance.found)
            std::printf("%s %s: NOISY: %s; the machine was likely disturbed while they ran\n",
                        r.run.c_str(), r.metric.c_str(), r.disturbance.why.c_str());
    if (!c.comparable())
        std::printf("nothing comparable: no run and metric is present in both %s and %s\n", baseline.c_str(),
                    candidate.c_str());
    else
        std::printf("%s: %s (threshold %g%%, alpha %g)\n", overall_verdict(c), counts.c_str(), 100 * options.threshold,
                    options.alpha);
    if (c.comparable() && c.inconclusive()) std::printf("%s\n", inconclusive_advice(c).c_str());
}

}  // namespace sph
