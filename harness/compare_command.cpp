// sphbench compare BASELINE CANDIDATE: a verdict per run and metric, as a table and JSON;
// the exit code is what CI acts on (0 fine, 1 regression, 2 usage or setup error, 3 nothing
// comparable, 4 inconclusive).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "commands.hpp"
#include "comparison_report.hpp"
#include "core/error.hpp"
#include "experiment_runner.hpp"
#include "io/atomic_file.hpp"
#include "regression_compare.hpp"
#include "solver_settings.hpp"

namespace sph {
namespace {

struct CompareArgs {
    std::string baseline, candidate, json, metrics = "update_ms,step_ms";
    double threshold = 0.05, alpha = 0.01, noise_ratio = 3;
};

std::vector<std::string> parse_metrics(const std::string& list) {
    std::vector<std::string> known = time_metrics();
    known.push_back("real_time");
    std::vector<std::string> out;
    std::stringstream in(list);
    std::string m;
    while (std::getline(in, m, ',')) {
        if (m.empty() || m == "counters") continue;  // counters are always compared
        if (std::find(known.begin(), known.end(), m) == known.end()) {
            std::string names;
            for (const auto& k : known) names += k + ", ";
            throw InputError("unknown metric '" + m + "' in --metrics (known: " + names + "counters)");
        }
        out.push_back(m);
    }
    return out;
}

std::string json_string(const std::string& s) {
    std::string out = "\"";
    for (char ch : s) {
        if (ch == '"' || ch == '\\') out += '\\', out += ch;
        else if (ch == '\n') out += "\\n";
        else if (static_cast<unsigned char>(ch) < 0x20) out += ' ';
        else out += ch;
    }
    return out + "\"";
}

std::string json_number(double v) { return std::isfinite(v) ? format_number(v) : "null"; }

std::string json_names(const std::vector<std::string>& names) {
    std::string out = "[";
    for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + json_string(names[i]);
    return out + "]";
}

void write_json(const std::string& path, const CompareArgs& a, const Comparison& c) {
    std::ostringstream j;
    j << "{\n  \"baseline\": " << json_string(a.baseline) << ",\n  \"candidate\": " << json_string(a.candidate)
      << ",\n  \"threshold\": " << json_number(a.threshold) << ",\n  \"alpha\": " << json_number(a.alpha)
      << ",\n  \"noise_ratio\": " << json_number(a.noise_ratio) << ",\n  \"comparisons\": [";
    for (std::size_t i = 0; i < c.rows.size(); ++i) {
        const auto& r = c.rows[i];
        j << (i ? "," : "") << "\n    {\"run\": " << json_string(r.run) << ", \"metric\": " << json_string(r.metric)
          << ", \"kind\": " << (r.counter ? "\"counter\"" : "\"time\"") << ", \"baseline\": " << json_number(r.baseline)
          << ", \"candidate\": " << json_number(r.candidate) << ", \"change\": " << json_number(r.change)
          << ", \"p\": " << (r.p < 0 ? "null" : json_number(r.p)) << ", \"n_baseline\": " << r.n_baseline
          << ", \"n_candidate\": " << r.n_candidate;
        if (!r.counter) {
            const Disturbance& d = r.disturbance;
            j << ", \"spread_baseline\": " << (d.spread_baseline < 0 ? "null" : json_number(d.spread_baseline))
              << ", \"spread_candidate\": " << (d.spread_candidate < 0 ? "null" : json_number(d.spread_candidate))
              << ", \"scatter_baseline\": " << (d.scatter_baseline < 0 ? "null" : json_number(d.scatter_baseline))
              << ", \"scatter_candidate\": " << (d.scatter_candidate < 0 ? "null" : json_number(d.scatter_candidate))
              << ", \"disturbed\": " << (d.found ? "true" : "false")
              << ", \"disturbance\": " << (d.found ? json_string(d.why) : "null");
        }
        j << ", \"verdict\": " << json_string(verdict_name(r.verdict)) << "}";
    }
    j << "\n  ],\n  \"only_in_baseline\": " << json_names(c.only_in_baseline)
      << ",\n  \"only_in_candidate\": " << json_names(c.only_in_candidate)
      << ",\n  \"regressed\": " << (c.regressed() ? "true" : "false")
      << ",\n  \"inconclusive\": " << (c.inconclusive() ? "true" : "false")
      << ",\n  \"verdict\": " << json_string(overall_verdict(c))
      << ",\n  \"exit_code\": " << comparison_exit_code(c) << "\n}\n";
    AtomicFile out(path);
    out.stream() << j.str();
    out.commit();
}

void compare(const CompareArgs& a, CommandContext& ctx) {
    CompareOptions options;
    options.threshold = a.threshold;
    options.alpha = a.alpha;
    options.noise_ratio = a.noise_ratio;
    options.time_metrics = parse_metrics(a.metrics);
    const ResultSet baseline = load_results(a.baseline);
    const ResultSet candidate = load_results(a.candidate);
    const Comparison c = compare_results(baseline, candidate, options);
    print_comparison(c, options, a.baseline, a.candidate);
    if (!a.json.empty()) write_json(a.json, a, c);
    ctx.exit_code = comparison_exit_code(c);
}

}  // namespace

void add_compare_command(CLI::App& app, CommandContext& ctx) {
    auto a = std::make_shared<CompareArgs>();
    CLI::App* cmd = app.add_subcommand(
        "compare", "compare two result sets run by run: SAME, FASTER, SLOWER, AMBIGUOUS (a change beyond the threshold "
                   "that the Mann-Whitney rank test cannot confirm, or too few samples) or NOISY (a disturbed machine: "
                   "the candidate far noisier than the baseline, its repetitions split in two groups, or one side's "
                   "repetitions disagreeing by the threshold or more) per time metric, counters exactly (COUNTER "
                   "CHANGED).\nExit codes:\n  0  no regression, every verdict known (SAME or FASTER; changes within "
                   "the threshold are SAME)\n  1  a regression: SLOWER or COUNTER CHANGED (wins over 4)\n  2  usage or "
                   "setup error (one sentence names the file, key or value)\n  3  nothing comparable\n  4  "
                   "inconclusive: some row AMBIGUOUS or NOISY and none a regression; rerun with more repetitions on a "
                   "quiet machine");
    cmd->add_option("baseline", a->baseline,
                    "result folder (with runs.csv), a runs.csv, or Google Benchmark JSON (--benchmark_format=json)")
        ->required();
    cmd->add_option("candidate", a->candidate, "the same kind of result, to judge against the baseline")->required();
    cmd->add_option("--threshold", a->threshold, "smallest relative change of the median that counts")
        ->check(CLI::Range(0.0, 10.0))
        ->capture_default_str();
    cmd->add_option("--alpha", a->alpha, "significance level of the rank test")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd->add_option("--noise-ratio", a->noise_ratio,
                    "NOISY where the candidate's interquartile range (relative to its median) is this many times the "
                    "baseline's, a split of its repetitions this many times the baseline's scatter, or one side's "
                    "repetitions scatter by 1/this of the change (each also at least the threshold)")
        ->check(CLI::Range(1.0, 1000.0))
        ->capture_default_str();
    cmd->add_option("--metrics", a->metrics,
                    "comma-separated time metrics (update_ms, step_ms, <phase>_ms, real_time); \"counters\" alone "
                    "compares only the work counters, which are always compared")
        ->capture_default_str();
    cmd->add_option("--json", a->json, "also write the verdicts to this JSON file");
    cmd->callback([a, &ctx] { compare(*a, ctx); });
}

}  // namespace sph
