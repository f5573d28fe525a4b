// Regression verdicts on generated results (A/A, an injected slowdown, a changed counter,
// nothing comparable, Google Benchmark JSON), and `run` then `compare` end to end on the host.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "scratch_folder.hpp"
#include "sphbench_driver.hpp"
#include "commands.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "experiment_spec.hpp"
#include "io/csv_writer.hpp"
#include "regression_compare.hpp"
#include "repetition_plan.hpp"

namespace fs = std::filesystem;

namespace sph {
namespace {

using test::sphbench;

struct FakeRun {
    std::string id;
    double update_ms = 10;       // median of the step times
    long candidates = 123456;
};

class CompareTest : public test::ScratchFolderTest {
protected:
    CompareTest() : ScratchFolderTest("sph_test_compare_") {}

    // A result folder as `run` writes it: runs.csv plus one step file per run, each step's
    // time drawn around the run's update time with 3% noise.
    std::string folder(const std::string& name, const std::vector<FakeRun>& runs, unsigned seed, long steps = 60) {
        const fs::path d = dir_ / name;
        std::mt19937 rng(seed);
        std::normal_distribution<double> noise(1.0, 0.03);
        CsvWriter table((d / "runs.csv").string(),
                        {"run_id", "config", "scene", "repetition", "particles", "fluid", "boundary", "update_ms_median",
                         "step_ms_median", "candidates_per_step", "neighbours_per_step", "ranges_per_step", "steps_file"},
                        {{"experiment", name}});
        for (const auto& r : runs) {
            const std::string steps_file = r.id + "_steps.csv";
            CsvWriter s((d / steps_file).string(), {"step", "update_ms", "step_ms"});
            std::vector<double> update;
            for (long k = 1; k <= steps; ++k) {
                const double u = r.update_ms * noise(rng);
                update.push_back(u);
                s.row({std::to_string(k), CsvWriter::fmt(u), CsvWriter::fmt(u * 1.5)});
            }
            s.commit();
            std::sort(update.begin(), update.end());
            const double median = update[update.size() / 2];
            table.row({r.id, r.id, "tank", "1", "1000", "800", "200", CsvWriter::fmt(median), CsvWriter::fmt(median * 1.5),
                       std::to_string(r.candidates), "5000", "27000", steps_file});
        }
        table.commit();
        return d.string();
    }

    // A result folder of one configuration run as repetitions, one row each with the given
    // median update time. Without steps (steps = 0) compare uses the repetition medians, as
    // for a spec that records only the summary; with steps each repetition's step times are
    // drawn around its median with `noise` relative spread.
    std::string repeated_folder(const std::string& name, const std::vector<double>& repetition_ms, unsigned seed,
                                long steps = 0, double noise = 0.03) {
        const fs::path d = dir_ / name;
        std::mt19937 rng(seed);
        std::normal_distribution<double> jitter(1.0, noise);
        CsvWriter table((d / "runs.csv").string(),
                        {"run_id", "config", "repetition", "update_ms_median", "candidates_per_step", "steps_file"},
                        {{"experiment", name}});
        for (std::size_t i = 0; i < repetition_ms.size(); ++i) {
            const std::string id = "tank_rep" + std::to_string(i + 1);
            std::string steps_file;
            double median = repetition_ms[i];
            if (steps > 0) {
                steps_file = id + "_steps.csv";
                CsvWriter s((d / steps_file).string(), {"step", "update_ms"});
                std::vector<double> update;
                for (long k = 1; k <= steps; ++k) {
                    update.push_back(repetition_ms[i] * jitter(rng));
                    s.row({std::to_string(k), CsvWriter::fmt(update.back())});
                }
                s.commit();
                std::sort(update.begin(), update.end());
                median = update[update.size() / 2];
            }
            table.row({id, "tank", std::to_string(i + 1), CsvWriter::fmt(median), "123456", steps_file});
        }
        table.commit();
        return d.string();
    }

    // Around `ms`, each repetition within +-0.5% (a quiet machine).
    static std::vector<double> quiet(double ms, int n, unsigned seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-0.005, 0.005);
        std::vector<double> v;
        for (int i = 0; i < n; ++i) v.push_back(ms * (1 + u(rng)));
        return v;
    }

    // Runs `sphbench compare` and returns its exit code and what it printed.
    std::pair<int, std::string> compare_printing(const std::vector<std::string>& args) {
        ::testing::internal::CaptureStdout();
        const int code = sphbench(args);
        return {code, ::testing::internal::GetCapturedStdout()};
    }

    static std::string text_of(const std::string& path) {
        std::ifstream in(path);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }

    std::string benchmark_json(const std::string& name, double slowdown, unsigned seed) {
        std::mt19937 rng(seed);
        std::normal_distribution<double> noise(1.0, 0.02);
        std::string text = "{\n  \"context\": {\"date\": \"now\", \"num_cpus\": 2},\n  \"benchmarks\": [\n";
        bool first = true;
        for (const char* bench : {"BM_Forces/4096", "BM_Search/4096"}) {
            for (int rep = 0; rep < 10; ++rep) {
                text += std::string(first ? "" : ",\n") + "    {\"name\": \"" + bench + "\", \"run_name\": \"" + bench +
                        "\", \"run_type\": \"iteration\", \"repetitions\": 10, \"repetition_index\": " +
                        std::to_string(rep) + ", \"iterations\": 100, \"real_time\": " +
                        CsvWriter::fmt(2.5e5 * slowdown * noise(rng)) + ", \"cpu_time\": 2.5e5, \"time_unit\": \"ns\"}";
                first = false;
            }
            text += std::string(",\n    {\"name\": \"") + bench + "_mean\", \"run_name\": \"" + bench +
                    "\", \"run_type\": \"aggregate\", \"aggregate_name\": \"mean\", \"real_time\": 1e9, \"time_unit\": \"ns\"}";
        }
        text += "\n  ]\n}\n";
        const std::string path = (dir_ / name).string();
        std::ofstream(path) << text;
        return path;
    }

};

const MetricComparison* find(const Comparison& c, const std::string& run, const std::string& metric) {
    for (const auto& r : c.rows)
        if (r.run == run && r.metric == metric) return &r;
    return nullptr;
}

TEST(RankTest, MannWhitneySeparatesShiftedSamplesAndNotEqualOnes) {
    std::vector<double> a, b, c;
    for (int i = 0; i < 20; ++i) {
        a.push_back(i);
        b.push_back(i + 0.5);
        c.push_back(i + 100);
    }
    EXPECT_GT(mann_whitney_p(a, b), 0.5);
    EXPECT_LT(mann_whitney_p(a, c), 1e-6);
    EXPECT_DOUBLE_EQ(mann_whitney_p({1, 1, 1}, {1, 1, 1}), 1.0);  // all tied
    // Symmetric in its arguments.
    EXPECT_NEAR(mann_whitney_p(a, c), mann_whitney_p(c, a), 1e-15);
}

TEST_F(CompareTest, AaComparisonFindsNoRegression) {
    const std::vector<FakeRun> runs = {{"tank-1"}, {"dambreak-2", 20}};
    const std::string a = folder("a", runs, 1), b = folder("b", runs, 2);
    const Comparison c = compare_results(load_results(a), load_results(b), CompareOptions{});
    ASSERT_TRUE(c.comparable());
    EXPECT_FALSE(c.regressed());
    for (const auto& r : c.rows) EXPECT_NE(r.verdict, Verdict::slower) << r.run << " " << r.metric;
    const MetricComparison* u = find(c, "tank-1", "update_ms");
    ASSERT_NE(u, nullptr);
    EXPECT_EQ(u->n_baseline, 60u);  // the per-step samples
    EXPECT_EQ(u->verdict, Verdict::same);
    EXPECT_EQ(sphbench({"compare", a, b}), 0);
}

TEST_F(CompareTest, TwentyPercentSlowdownIsFlaggedSlower) {
    const std::string a = folder("a", {{"tank-1"}, {"dambreak-2"}}, 1);
    const std::string b = folder("b", {{"tank-1", 12.0}, {"dambreak-2"}}, 2);
    const Comparison c = compare_results(load_results(a), load_results(b), CompareOptions{});
    const MetricComparison* u = find(c, "tank-1", "update_ms");
    ASSERT_NE(u, nullptr);
    EXPECT_EQ(u->verdict, Verdict::slower);
    EXPECT_NEAR(u->change, 0.2, 0.03);
    EXPECT_LT(u->p, 1e-6);
    EXPECT_EQ(find(c, "dambreak-2", "update_ms")->verdict, Verdict::same);
    EXPECT_TRUE(c.regressed());
    const std::string json = (dir_ / "verdict.json").string();
    EXPECT_EQ(sphbench({"compare", a, b, "--json", json}), 1);
    std::ifstream in(json);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"verdict\": \"SLOWER\""), std::string::npos) << text;
    // The reverse direction is FASTER, which is no regression.
    const Comparison back = compare_results(load_results(b), load_results(a), CompareOptions{});
    EXPECT_EQ(find(back, "tank-1", "update_ms")->verdict, Verdict::faster);
    EXPECT_EQ(sphbench({"compare", b, a}), 0);
    // Too few samples to tell: AMBIGUOUS, not SLOWER, and inconclusive (exit 4), not a pass.
    const std::string few_a = folder("few_a", {{"tank-1"}}, 1, 4), few_b = folder("few_b", {{"tank-1", 12.0}}, 2, 4);
    EXPECT_EQ(compare_results(load_results(few_a), load_results(few_b), CompareOptions{}).rows.front().verdict,
              Verdict::ambiguous);
    const auto [code, printed] = compare_printing({"compare", few_a, few_b, "--metrics", "update_ms"});
    EXPECT_EQ(code, exit_inconclusive) << printed;
    EXPECT_NE(printed.find("INCONCLUSIVE"), std::string::npos) << printed;
    EXPECT_NE(printed.find("inconclusive: rerun the candidate with more repetitions"), std::string::npos) << printed;
    EXPECT_EQ(printed.find("likely disturbed"), std::string::npos) << printed;  // ambiguous, not noisy
}

// The case of issue 26: 8 repetitions on a quiet machine, then 8 while two CPU-bound processes
// competed for the cores (5 of them at 17-18 ms, 3 at the baseline's 9.5 ms). It said
// "+49.7% p 0.041 AMBIGUOUS" and exited 0; now it is NOISY, says why and what to do, and exits 4.
TEST_F(CompareTest, LoadedMachineCandidateIsInconclusiveNotAPass) {
    const std::string base = repeated_folder("base", quiet(9.5, 8, 1), 1);
    std::vector<double> loaded = {17.4, 9.52, 17.9, 17.2, 9.47, 17.6, 9.55, 17.8};
    const std::string cand = repeated_folder("loaded", loaded, 2);
    const Comparison c = compare_results(load_results(base), load_results(cand), CompareOptions{});
    const MetricComparison* u = find(c, "tank", "update_ms");
    ASSERT_NE(u, nullptr);
    EXPECT_EQ(u->n_candidate, 8u);  // the repetition medians: no step files
    EXPECT_GT(u->change, 0.05);
    EXPECT_EQ(u->verdict, Verdict::noisy);
    EXPECT_TRUE(u->disturbance.found);
    EXPECT_GT(u->disturbance.spread_candidate, 0.3);   // (17.4 - 9.5) / 17.5 or so
    EXPECT_LT(u->disturbance.spread_baseline, 0.01);
    EXPECT_EQ(u->disturbance.fast_group, 3u);
    EXPECT_EQ(u->disturbance.slow_group, 5u);
    EXPECT_FALSE(c.regressed());
    EXPECT_TRUE(c.inconclusive());
    EXPECT_EQ(comparison_exit_code(c), 4);

    const std::string json = (dir_ / "loaded.json").string();
    const auto [code, printed] = compare_printing({"compare", base, cand, "--json", json});
    EXPECT_EQ(code, 4) << printed;
    EXPECT_NE(printed.find("NOISY"), std::string::npos) << printed;
    EXPECT_NE(printed.find("tank update_ms: NOISY: the candidate is far noisier than the baseline"), std::string::npos)
        << printed;
    EXPECT_NE(printed.find("split into 3 near 9.5"), std::string::npos) << printed;
    EXPECT_NE(printed.find("the machine was likely disturbed"), std::string::npos) << printed;
    EXPECT_NE(printed.find("inconclusive: rerun the candidate with more repetitions"), std::string::npos) << printed;
    EXPECT_NE(printed.find("on a quiet machine"), std::string::npos) << printed;
    const std::string j = text_of(json);
    EXPECT_NE(j.find("\"verdict\": \"NOISY\""), std::string::npos) << j;
    EXPECT_NE(j.find("\"disturbed\": true"), std::string::npos) << j;
    EXPECT_NE(j.find("\"inconclusive\": true"), std::string::npos) << j;
    EXPECT_NE(j.find("\"verdict\": \"INCONCLUSIVE\""), std::string::npos) << j;
    EXPECT_NE(j.find("\"exit_code\": 4"), std::string::npos) << j;

    // The same two sets with step files (60 steps each, 3% noise): the pooled steps say the same.
    const std::string base_steps = repeated_folder("base_steps", quiet(9.5, 8, 1), 3, 60);
    const std::string cand_steps = repeated_folder("loaded_steps", loaded, 4, 60);
    const Comparison s = compare_results(load_results(base_steps), load_results(cand_steps), CompareOptions{});
    EXPECT_EQ(find(s, "tank", "update_ms")->n_candidate, 480u);
    EXPECT_EQ(find(s, "tank", "update_ms")->verdict, Verdict::noisy);
    EXPECT_EQ(sphbench({"compare", base_steps, cand_steps}), 4);
}

// A clean A/A of repeated runs passes, with and without step files.
TEST_F(CompareTest, QuietRepetitionsCompareCleanAndExitZero) {
    for (long steps : {0L, 60L}) {
        const std::string a = repeated_folder("a" + std::to_string(steps), quiet(9.5, 8, 1), 1, steps);
        const std::string b = repeated_folder("b" + std::to_string(steps), quiet(9.5, 8, 2), 2, steps);
        const Comparison c = compare_results(load_results(a), load_results(b), CompareOptions{});
        const MetricComparison* u = find(c, "tank", "update_ms");
        ASSERT_NE(u, nullptr);
        EXPECT_EQ(u->verdict, Verdict::same) << steps;
        EXPECT_FALSE(u->disturbance.found) << u->disturbance.why;
        const std::string json = (dir_ / ("aa" + std::to_string(steps) + ".json")).string();
        const auto [code, printed] = compare_printing({"compare", a, b, "--json", json});
        EXPECT_EQ(code, 0) << printed;
        EXPECT_EQ(printed.find("inconclusive"), std::string::npos) << printed;
        const std::string j = text_of(json);
        EXPECT_NE(j.find("\"verdict\": \"NO REGRESSION\""), std::string::npos) << j;
        EXPECT_NE(j.find("\"exit_code\": 0"), std::string::npos) << j;
    }
}

// A real 20% slowdown of every repetition on a quiet machine is a regression, not noise.
TEST_F(CompareTest, UniformSlowdownOfRepetitionsIsSlowerNotNoisy) {
    std::vector<double> slow = quiet(9.5 * 1.2, 8, 2);
    const std::string a = repeated_folder("a", quiet(9.5, 8, 1), 1), b = repeated_folder("b", slow, 2);
    const Comparison c = compare_results(load_results(a), load_results(b), CompareOptions{});
    const MetricComparison* u = find(c, "tank", "update_ms");
    ASSERT_NE(u, nullptr);
    EXPECT_EQ(u->verdict, Verdict::slower);
    EXPECT_FALSE(u->disturbance.found) << u->disturbance.why;
    const std::string json = (dir_ / "slow.json").string();
    EXPECT_EQ(sphbench({"compare", a, b, "--json", json}), 1);
    const std::string j = text_of(json);
    EXPECT_NE(j.find("\"verdict\": \"SLOWER\""), std::string::npos) << j;
    EXPECT_NE(j.find("\"verdict\": \"REGRESSION\""), std::string::npos) << j;
}

// A noisy candidate is NOISY whatever its median says: within the threshold (3 of 8 loaded,
// the median unmoved, which was SAME) and faster (a real speedup measured on a loaded machine).
TEST_F(CompareTest, NoisyCandidateIsNeverSameOrFaster) {
    const std::string base = repeated_folder("base", quiet(9.5, 8, 1), 1);
    const std::string few_loaded = repeated_folder("few", {9.5, 17.5, 9.48, 9.52, 17.2, 9.51, 9.49, 17.8}, 2);
    const Comparison c = compare_results(load_results(base), load_results(few_loaded), CompareOptions{});
    EXPECT_LT(std::abs(find(c, "tank", "update_ms")->change), 0.05);
    EXPECT_EQ(find(c, "tank", "update_ms")->verdict, Verdict::noisy);
    EXPECT_EQ(sphbench({"compare", base, few_loaded}), 4);

    const std::string faster = repeated_folder("faster", {6.0, 6.02, 11.0, 5.98, 11.5, 6.01, 10.8, 5.99}, 3);
    const Comparison f = compare_results(load_results(base), load_results(faster), CompareOptions{});
    EXPECT_LT(find(f, "tank", "update_ms")->change, -0.05);
    EXPECT_EQ(find(f, "tank", "update_ms")->verdict, Verdict::noisy);
    EXPECT_EQ(sphbench({"compare", base, faster}), 4);
}

// The two signs separately, on the function itself.
TEST(Disturbance, SpreadAndSplitAreEachEnoughAndOrdinaryNoiseIsNeither) {
    const CompareOptions o;
    const std::vector<double> base = {9.50, 9.52, 9.48, 9.51, 9.49, 9.53, 9.47, 9.50};
    // Ordinary noise: more spread than the baseline's, but far less than the threshold, and no gap.
    const std::vector<double> wobbly = {9.46, 9.56, 9.44, 9.54, 9.48, 9.58, 9.42, 9.50};
    EXPECT_FALSE(find_disturbance(base, wobbly, base, wobbly, 0.0, o).found);
    // Spread alone (no repetitions to split): a continuous smear from 9.5 to 14.
    const std::vector<double> smear = {9.5, 10.1, 10.8, 11.4, 12.0, 12.7, 13.3, 14.0};
    const Disturbance spread = find_disturbance(base, smear, {}, {}, 0.23, o);
    EXPECT_TRUE(spread.found);
    EXPECT_NE(spread.why.find("interquartile range"), std::string::npos) << spread.why;
    EXPECT_EQ(spread.fast_group, 0u);
    // Split alone: 2 of 10 repetitions at the baseline's speed, 8 at 17.5 ms. The pooled steps'
    // spread (their quartiles both in the slow group) does not show it; the repetitions do.
    const std::vector<double> two_fast = {9.5, 17.5, 17.4, 9.52, 17.6, 17.5, 17.45, 17.55, 17.48, 17.52};
    std::vector<double> steps_b, steps_c;
    for (double r : base)
        for (int k = -30; k < 30; ++k) steps_b.push_back(r * (1 + 0.001 * k));
    for (double r : two_fast)
        for (int k = -30; k < 30; ++k) steps_c.push_back(r * (1 + 0.001 * k));
    const Disturbance split = find_disturbance(steps_b, steps_c, base, two_fast, 0.84, o);
    EXPECT_TRUE(split.found);
    EXPECT_EQ(split.fast_group, 2u);
    EXPECT_EQ(split.slow_group, 8u);
    EXPECT_NEAR(split.fast_median, 9.51, 0.01);
    EXPECT_NEAR(split.slow_median, 17.5, 0.01);
    EXPECT_EQ(split.why.find("interquartile range"), std::string::npos) << split.why;
    // One outlier is not a split (a group needs two repetitions).
    const std::vector<double> one_fast = {9.5, 17.5, 17.4, 17.52, 17.6, 17.5, 17.45, 17.55};
    EXPECT_FALSE(find_disturbance(base, one_fast, base, one_fast, 0.84, o).found);
    // A baseline as bimodal as the candidate: nothing new.
    EXPECT_FALSE(find_disturbance(two_fast, two_fast, two_fast, two_fast, 0.0, o).found);
}

// Scatter: one side's repetitions disagree. The repetition medians (ms) of an A/A of a small
// host tank, 8 repetitions each, measured on this 2-core machine at a load average of 10: the
// rank test on their 320 pooled steps said FASTER, p 8e-18, change -50%.
TEST(Disturbance, RepetitionsThatDisagreeByTheChangeAreNoisyOnEitherSide) {
    const CompareOptions o;
    const std::vector<double> a = {25.9, 26.05, 24.69, 22.84, 8.12, 10.49, 10.31, 6.25};
    const std::vector<double> b = {8.24, 6.91, 10.52, 7.93, 9.87, 10.14, 10.06, 10.05};
    const Disturbance d = find_disturbance(a, b, a, b, -0.497, o);
    EXPECT_TRUE(d.found);
    EXPECT_GT(d.scatter_baseline, 0.8);
    EXPECT_NEAR(d.scatter_candidate, 0.19, 0.01);
    EXPECT_NE(d.why.find("the baseline's 8 repetitions disagree"), std::string::npos) << d.why;
    EXPECT_NE(d.why.find("the candidate's 8 repetitions disagree"), std::string::npos) << d.why;
    EXPECT_TRUE(d.in_baseline);
    // Either side alone is enough: the noisy side as the candidate, a quiet one as the baseline.
    const std::vector<double> quiet_b = {9.5, 9.52, 9.48, 9.51, 9.49, 9.53, 9.47, 9.5};
    EXPECT_TRUE(find_disturbance(a, quiet_b, a, quiet_b, -0.5, o).found);
    EXPECT_TRUE(find_disturbance(quiet_b, b, quiet_b, b, 0.05, o).found);
    EXPECT_FALSE(find_disturbance(quiet_b, b, quiet_b, b, 0.05, o).in_baseline);
    // Repetitions scattered by 6.5% measure a 40% slowdown (beyond 3 scatters), but not a
    // 10% one; scattered by 2.3%, under the threshold, they measure both.
    const std::vector<double> six = {10.0, 10.4, 9.6, 10.7, 9.3, 10.3, 9.7, 10.0};      // IQR 6.5%
    const std::vector<double> three = {10.0, 10.15, 9.85, 10.3, 9.7, 10.1, 9.9, 10.0};  // IQR 2.3%
    std::vector<double> six_slow, three_slow;
    for (double v : six) six_slow.push_back(v * 1.4);
    for (double v : three) three_slow.push_back(v * 1.1);
    EXPECT_FALSE(find_disturbance(six, six_slow, six, six_slow, 0.4, o).found);
    EXPECT_TRUE(find_disturbance(six, six_slow, six, six_slow, 0.1, o).found);
    EXPECT_FALSE(find_disturbance(three, three_slow, three, three_slow, 0.1, o).found);
    // Fewer than 4 repetitions: no scatter to judge.
    EXPECT_FALSE(find_disturbance({}, {}, {10.0, 14.0, 6.0}, {10.0, 14.0, 6.0}, 0.0, o).found);
}

TEST_F(CompareTest, ChangedCounterIsFlaggedEvenWhenOnlyCountersAreCompared) {
    const std::string a = folder("a", {{"tank-1"}}, 1);
    const std::string b = folder("b", {{"tank-1", 10, 123457}}, 1);
    CompareOptions counters_only;
    counters_only.time_metrics.clear();
    const Comparison c = compare_results(load_results(a), load_results(b), counters_only);
    const MetricComparison* k = find(c, "tank-1", "candidates_per_step");
    ASSERT_NE(k, nullptr);
    EXPECT_EQ(k->verdict, Verdict::counter_changed);
    EXPECT_EQ(find(c, "tank-1", "update_ms"), nullptr);
    EXPECT_EQ(find(c, "tank-1", "neighbours_per_step")->verdict, Verdict::same);
    EXPECT_EQ(sphbench({"compare", a, b, "--metrics", "counters"}), 1);
}

TEST_F(CompareTest, UnmatchedRunsAreNothingComparable) {
    const std::string a = folder("a", {{"tank-1"}}, 1), b = folder("b", {{"tank-2"}}, 2);
    const Comparison c = compare_results(load_results(a), load_results(b), CompareOptions{});
    EXPECT_FALSE(c.comparable());
    EXPECT_EQ(c.only_in_baseline, std::vector<std::string>{"tank-1"});
    EXPECT_EQ(sphbench({"compare", a, b}), 3);
}

TEST_F(CompareTest, SetupErrorsExitWithTwo) {
    const std::string a = folder("a", {{"tank-1"}}, 1);
    EXPECT_EQ(sphbench({"compare", a, (dir_ / "missing").string()}), 2);
    fs::create_directories(dir_ / "empty");
    EXPECT_EQ(sphbench({"compare", a, (dir_ / "empty").string()}), 2);
    EXPECT_EQ(sphbench({"compare", a, a, "--metrics", "update_s"}), 2);
    std::ofstream(dir_ / "broken.csv") << "run_id,config\nonly-one-cell\n";
    EXPECT_EQ(sphbench({"compare", a, (dir_ / "broken.csv").string()}), 2);
}

TEST_F(CompareTest, GoogleBenchmarkJsonPairs) {
    const std::string base = benchmark_json("base.json", 1.0, 1), same = benchmark_json("same.json", 1.0, 2);
    const std::string slow = benchmark_json("slow.json", 1.2, 3);
    const Comparison aa = compare_results(load_results(base), load_results(same), CompareOptions{});
    ASSERT_EQ(aa.rows.size(), 2u);  // two benchmarks, real_time each; aggregates ignored
    EXPECT_EQ(aa.rows[0].n_baseline, 10u);
    EXPECT_FALSE(aa.regressed());
    EXPECT_EQ(sphbench({"compare", base, same}), 0);
    const Comparison ab = compare_results(load_results(base), load_results(slow), CompareOptions{});
    EXPECT_EQ(find(ab, "BM_Forces/4096", "real_time")->verdict, Verdict::slower);
    EXPECT_EQ(sphbench({"compare", base, slow}), 1);
    std::ofstream(dir_ / "bad.json") << "{\"benchmarks\": [ {\"name\": }";
    EXPECT_EQ(sphbench({"compare", base, (dir_ / "bad.json").string()}), 2);
}

// The real `run` path on the host backend, twice, then `compare` of the two on counters.
TEST_F(CompareTest, RunTwiceOnTheHostThenCountersMatch) {
    const std::string spec = (dir_ / "tiny.toml").string();
    std::ofstream(spec) << "name = \"tiny\"\nreproduces = \"the end-to-end test\"\nsteps = 5\nseed = 7\n"
                           "record = [\"summary\", \"steps\"]\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"tank\"\nset = { dp = 0.05 }\n";
    const std::string out1 = (dir_ / "out1").string(), out2 = (dir_ / "out2").string();
    ASSERT_EQ(sphbench({"run", spec, "--backend", "host", "--out", out1, "--quiet"}), 0);
    ASSERT_EQ(sphbench({"run", spec, "--backend", "host", "--out", out2, "--quiet"}), 0);

    const CsvTable t = read_csv(out1 + "/tiny/runs.csv");
    for (const char* column : {"run_id", "scene", "repetition", "backend", "device", "particles", "fluid", "boundary", "dp",
                               "steps", "warmup", "cells_per_support", "merge", "fixed_dt", "cfl", "diffusion", "set.dp",
                               "update_ms_median", "update_ms_q1", "update_ms_q3", "update_ms_min", "step_ms_median",
                               "forces_ms_median", "neighbour_list_ms_min", "mparticle_steps_per_s",
                               "bytes_per_particle", "candidates_per_step", "neighbours_per_step", "ranges_per_step",
                               "sim_time", "wall_s", "steps_file"})
        EXPECT_GE(t.column(column), 0) << column;
    ASSERT_EQ(t.rows.size(), 1u);
    EXPECT_EQ(t.cell(0, "run_id"), "tank");
    EXPECT_EQ(t.cell(0, "backend"), "host");
    EXPECT_EQ(t.cell(0, "steps_file"), "tank_steps.csv");
    EXPECT_TRUE(fs::exists(out1 + "/tiny/tank_steps.csv"));
    EXPECT_GT(std::stod(t.cell(0, "neighbours_per_step")), 0);
    for (const char* key : {"git_commit", "build_type", "backend", "host", "date", "command_line", "spec", "spec_hash",
                            "binary_hash", "overrides", "seed", "scale", "reduced_scale"})
        EXPECT_TRUE(t.meta(key).has_value()) << key;
    EXPECT_EQ(t.meta("seed").value(), "7");
    EXPECT_EQ(t.meta("reduced_scale").value(), "no");
    EXPECT_EQ(t.meta("overrides").value(), "--backend host");
    EXPECT_TRUE(read_csv(out1 + "/tiny/tank_steps.csv").meta("spec_hash").has_value());

    EXPECT_EQ(sphbench({"compare", out1 + "/tiny", out2 + "/tiny", "--metrics", "counters"}), 0);

    // Unchanged spec, binary and options: not run again.
    const auto before = fs::last_write_time(out1 + "/tiny/runs.csv");
    ::testing::internal::CaptureStdout();
    EXPECT_EQ(sphbench({"run", spec, "--backend", "host", "--out", out1, "--quiet"}), 0);
    EXPECT_NE(::testing::internal::GetCapturedStdout().find("tiny: up to date"), std::string::npos);
    EXPECT_EQ(fs::last_write_time(out1 + "/tiny/runs.csv"), before);
}

// A case file is part of what the results were made from: edited (its geometry, its gauges),
// the results are run again, as for an edited spec; untouched, they are skipped.
TEST_F(CompareTest, AnEditedCaseFileMakesItsExperimentsResultsOutOfDate) {
    const std::string case_file = (dir_ / "tank.toml").string(), spec = (dir_ / "tiny-case.toml").string();
    const std::string tank = "[case]\ndp = 0.05\n[case.tank]\nmin = [0, 0, 0]\nmax = [0.3, 0.2, 0.3]\n"
                             "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.15, 0.2, 0.15]\n";
    std::ofstream(case_file) << tank;
    std::ofstream(spec) << "name = \"tiny-case\"\nreproduces = \"the freshness test\"\nsteps = 3\n"
                           "record = [\"summary\"]\n[[runs]]\nscene = \"case:tank.toml\"\nlabel = \"tank\"\n";
    const std::string out = (dir_ / "out-case").string();
    ASSERT_EQ(sphbench({"run", spec, "--backend", "host", "--out", out, "--quiet"}), 0);
    const CsvTable t = read_csv(out + "/tiny-case/runs.csv");
    ASSERT_TRUE(t.meta("case_hashes").has_value());
    EXPECT_EQ(t.meta("case_hashes").value(), case_file + "=" + spec_hash(case_file));
    const auto run_again = [&] {
        ::testing::internal::CaptureStdout();
        EXPECT_EQ(sphbench({"run", spec, "--backend", "host", "--out", out, "--quiet"}), 0);
        return ::testing::internal::GetCapturedStdout().find("tiny-case: up to date") == std::string::npos;
    };
    EXPECT_FALSE(run_again());  // nothing changed
    std::ofstream(case_file) << tank << "[[case.gauges]]\nkind = \"pressure\"\nx = 0.05\ny = 0.1\nz = 0.05\nevery = 0.001\n";
    EXPECT_TRUE(run_again());   // the case gained a gauge
    EXPECT_FALSE(run_again());
}

// What `run --baseline` adds: doubling while AMBIGUOUS, up to the cap; nothing while NOISY or
// known. The comparisons are of generated repetitions (a baseline of 8 at 9.5 ms).
TEST_F(CompareTest, RepetitionPlanDoublesAmbiguousConfigurationsUpToTheCap) {
    const std::string base = repeated_folder("base", quiet(9.5, 8, 1), 1);
    const auto compare_with = [&](const std::string& name, const std::vector<double>& reps) {
        return compare_results(load_results(base), load_results(repeated_folder(name, reps, 2)), CompareOptions{});
    };
    PlannedRun model;
    model.config = "tank";
    model.run_id = "tank";
    model.label = "tank";
    const std::vector<PlannedRun> planned = {model};
    // One repetition 20% slower: AMBIGUOUS (too few samples); 1 -> 2, 2 -> 4, 4 -> 8, 8 -> 16, capped.
    const Comparison one = compare_with("one", {11.4});
    ASSERT_EQ(find(one, "tank", "update_ms")->verdict, Verdict::ambiguous);
    RepetitionPlan plan = more_repetitions(one, planned, {{"tank", 1}}, 16);
    ASSERT_EQ(plan.runs.size(), 1u);
    EXPECT_EQ(plan.runs[0].run_id, "tank_rep2");
    EXPECT_EQ(plan.runs[0].repetition, 2);
    EXPECT_EQ(plan.runs[0].config, "tank");
    plan = more_repetitions(one, planned, {{"tank", 4}}, 16);
    ASSERT_EQ(plan.runs.size(), 4u);
    EXPECT_EQ(plan.runs.front().run_id, "tank_rep5");
    EXPECT_EQ(plan.runs.back().run_id, "tank_rep8");
    EXPECT_EQ(more_repetitions(one, planned, {{"tank", 12}}, 16).runs.size(), 4u);  // 13..16
    plan = more_repetitions(one, planned, {{"tank", 16}}, 16);
    EXPECT_TRUE(plan.runs.empty());
    EXPECT_EQ(plan.capped, std::vector<std::string>{"tank"});
    // Known verdicts (SLOWER, SAME) and NOISY ones get none, and are not "capped".
    const Comparison slower = compare_with("slower", quiet(11.4, 8, 3));
    ASSERT_EQ(find(slower, "tank", "update_ms")->verdict, Verdict::slower);
    const Comparison same = compare_with("same", quiet(9.5, 8, 4));
    const Comparison noisy = compare_with("noisy", {17.4, 9.52, 17.9, 17.2, 9.47, 17.6, 9.55, 17.8});
    ASSERT_EQ(find(noisy, "tank", "update_ms")->verdict, Verdict::noisy);
    for (const Comparison* c : {&slower, &same, &noisy}) {
        const RepetitionPlan none = more_repetitions(*c, planned, {{"tank", 8}}, 16);
        EXPECT_TRUE(none.runs.empty());
        EXPECT_TRUE(none.capped.empty());
    }
}

// `run --baseline` on the host: a baseline of one repetition (written here, at 1e6 ms) keeps
// the verdict AMBIGUOUS however many repetitions the candidate has, so repetitions are added,
// 1 -> 2 -> 3, up to the cap, and the run exits 4. (With 3 repetitions no noise test applies,
// so the host's load cannot change this.)
TEST_F(CompareTest, RunWithBaselineAddsRepetitionsUpToTheCap) {
    const fs::path one = dir_ / "one";
    {
        CsvWriter table((one / "runs.csv").string(), {"run_id", "config", "repetition", "update_ms_median"}, {});
        table.row({"tank", "tank", "1", "1000000"});
        table.commit();
    }
    const std::string spec = (dir_ / "tiny.toml").string();
    std::ofstream(spec) << "name = \"tiny\"\nreproduces = \"the --baseline test\"\nsteps = 3\n"
                           "record = [\"summary\"]\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"tank\"\nset = { dp = 0.05 }\n";
    const auto repetitions = [](const std::string& out) {
        const CsvTable t = read_csv(out + "/tiny/runs.csv");
        std::vector<std::string> reps;
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
            EXPECT_EQ(t.cell(i, "config"), "tank");
            reps.push_back(t.cell(i, "run_id") + ":" + t.cell(i, "repetition"));
        }
        return reps;
    };
    const std::string out = (dir_ / "out").string();
    auto [code, printed] = compare_printing({"run", spec, "--backend", "host", "--out", out, "--quiet", "--baseline",
                                             one.string(), "--max-repetitions", "3"});
    EXPECT_EQ(code, exit_inconclusive) << printed;
    EXPECT_EQ(repetitions(out), (std::vector<std::string>{"tank:1", "tank_rep2:2", "tank_rep3:3"}));
    EXPECT_NE(printed.find("tiny: inconclusive against"), std::string::npos) << printed;
    EXPECT_NE(printed.find("AMBIGUOUS"), std::string::npos) << printed;
    EXPECT_NE(printed.find("tank: still AMBIGUOUS after 3 repetitions"), std::string::npos) << printed;
    EXPECT_NE(printed.find("inconclusive: rerun"), std::string::npos) << printed;
    EXPECT_NE(printed.find("rerun the baseline too: it has 1 sample(s) of tank update_ms"), std::string::npos) << printed;
    // Up to date: nothing run again; the three there are at the cap already.
    std::tie(code, printed) = compare_printing({"run", spec, "--backend", "host", "--out", out, "--quiet", "--baseline",
                                                one.string(), "--max-repetitions", "3"});
    EXPECT_EQ(code, exit_inconclusive) << printed;
    EXPECT_EQ(printed.find("tiny: inconclusive against"), std::string::npos) << printed;
    EXPECT_EQ(repetitions(out).size(), 3u);
    // A results root finds the result folder by the experiment's name: here the run's own, SAME.
    std::tie(code, printed) = compare_printing({"run", spec, "--backend", "host", "--out", out, "--quiet", "--baseline", out});
    EXPECT_EQ(code, 0) << printed;
    EXPECT_NE(printed.find("NO REGRESSION"), std::string::npos) << printed;

    // Bad input: exit 2, nothing run.
    const std::string bad = (dir_ / "bad").string();
    EXPECT_EQ(sphbench({"run", spec, "--backend", "host", "--out", bad, "--quiet", "--baseline", one.string(),
                        "--max-repetitions", "0"}),
              exit_usage);
    EXPECT_EQ(sphbench({"run", spec, "--backend", "host", "--out", bad, "--quiet", "--baseline",
                        (dir_ / "missing").string()}),
              exit_usage);
    EXPECT_EQ(sphbench({"run", spec, "--backend", "host", "--out", bad, "--quiet", "--baseline", dir_.string()}),
              exit_usage);  // neither a result folder nor a root holding tiny/
    EXPECT_FALSE(fs::exists(bad + "/tiny/runs.csv"));
}

TEST_F(CompareTest, FailingRunIsNamedAndLeavesNoTable) {
    const std::string spec = (dir_ / "broken.toml").string();
    std::ofstream(spec) << "name = \"broken\"\nreproduces = \"a failing run\"\nsteps = 2\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"bad-tank\"\nset = { colour = \"blue\" }\n";
    const std::string out = (dir_ / "out").string();
    std::vector<std::string> args = {"sphbench", "run", spec, "--backend", "host", "--out", out, "--quiet"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    CLI::App app{"sphbench"};
    CommandContext ctx{int(argv.size()), argv.data()};
    add_run_command(app, ctx);
    try {
        app.parse(int(argv.size()), argv.data());
        FAIL() << "the run should fail";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bad-tank"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("colour"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(out + "/broken/runs.csv"));
}

}  // namespace
}  // namespace sph
