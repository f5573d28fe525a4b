// Runs to a simulated time, for any scene (issue 26), and what a whole run costs (issue 25):
// the end time stops a run at the first step that reaches it and --steps caps it; the summary
// and runs.csv give steps, simulated time, wall seconds and seconds per simulated second; with
// Verlet lists the rebuild steps and the listed steps add up to the steps. Small scenes on the
// host backend; the reference for each is a plain run of the same scene without an end time.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "experiment_spec.hpp"
#include "scene_run.hpp"
#include "scratch_folder.hpp"
#include "sphbench_driver.hpp"

namespace fs = std::filesystem;

namespace sph {
namespace {

using test::sphbench;

// DualSPHysics' dam break has no validation metric: an end time must not need one.
const std::map<std::string, std::string> dambreak_options = {{"dp", "0.05"}};

SceneRunRequest dambreak_request() {
    SceneRunRequest req;
    req.scene = "dsph-dambreak";
    req.scene_options = dambreak_options;
    req.progress = false;
    return req;
}

// The simulated time after each of the first n steps, from a run without an end time.
std::vector<double> step_times(long n) {
    SceneRunRequest req = dambreak_request();
    req.steps = n;
    const SceneRunResult r = run_scene(req);
    std::vector<double> t;
    for (const auto& s : r.steps) t.push_back(s.time);
    return t;
}

double number(const CsvTable& t, const std::string& column) {
    EXPECT_GE(t.column(column), 0) << column;
    return std::stod(t.cell(0, column));
}

class WholeRunTest : public test::ScratchFolderTest {
protected:
    WholeRunTest() : ScratchFolderTest("sph_whole_run_") {}
    std::string write(const std::string& name, const std::string& text) {
        const std::string path = (dir_ / name).string();
        std::ofstream(path) << text;
        return path;
    }
};

TEST(EndTime, StopsAnySceneAtTheFirstStepThatReachesIt) {
    const std::vector<double> t = step_times(12);
    ASSERT_EQ(t.size(), 12u);
    // Between two steps' times, and on one exactly: the first step whose time is >= T ends it.
    for (const auto& [end_time, expected] : {std::pair{0.5 * (t[5] + t[6]), 7L}, std::pair{t[8], 9L}}) {
        SceneRunRequest req = dambreak_request();
        req.end_time = end_time;
        req.steps = 0;  // no cap
        const SceneRunResult r = run_scene(req);
        EXPECT_EQ(r.steps_taken, expected) << "end time " << end_time;
        EXPECT_EQ(r.stopped_by, "end_time");
        EXPECT_EQ(r.sim_time, t[std::size_t(expected - 1)]);
        EXPECT_GE(r.sim_time, end_time);
        ASSERT_FALSE(r.steps.empty());
        EXPECT_LT(r.sim_time - end_time, r.steps.back().dt) << "within one step of the end time";
        EXPECT_EQ(r.cost.steps, expected);
        EXPECT_GT(r.wall_seconds, 0);
        EXPECT_DOUBLE_EQ(r.seconds_per_sim_second(), r.wall_seconds / r.sim_time);
    }
}

TEST(EndTime, StepsCapTheRunWarmUpIncludedAndSayWhichStopped) {
    const std::vector<double> t = step_times(6);
    SceneRunRequest req = dambreak_request();
    req.end_time = 10.0;  // far beyond what 6 steps reach
    req.warmup = 2;
    req.steps = 4;
    const SceneRunResult capped = run_scene(req);
    EXPECT_EQ(capped.steps_taken, 6);
    EXPECT_EQ(capped.steps.size(), 4u);  // the window after the warm-up
    EXPECT_EQ(capped.stopped_by, "steps");
    EXPECT_EQ(capped.sim_time, t[5]);
    // The cap does not move an end time that comes first.
    req.end_time = t[2];
    const SceneRunResult timed = run_scene(req);
    EXPECT_EQ(timed.steps_taken, 3);
    EXPECT_EQ(timed.stopped_by, "end_time");
}

// rebuild_every = k: the constructor builds the lists, then step n rebuilds them when n - 1
// is a multiple of k. Counting them from the simulation's list builds must say so.
TEST(RunCost, RebuildStepsAndListedStepsAddUpToTheSteps) {
    SceneRunRequest req = dambreak_request();
    req.solver.search.verlet = true;
    req.solver.search.rebuild_every = 3;
    req.steps = 11;
    req.warmup = 2;
    const SceneRunResult r = run_scene(req);
    const long n = 13;
    ASSERT_EQ(r.cost.steps, n);
    EXPECT_EQ(r.cost.rebuild_steps, (n - 1) / 3);
    EXPECT_EQ(r.cost.rebuild_steps + r.cost.listed_steps(), r.steps_taken);
    EXPECT_GT(r.list_bytes, 0u);
    // The means times their counts give back the steps' wall clocks (the window's here, past
    // the warm-up, checked against the recorded steps of a run without warm-up below).
    req.warmup = 0;
    req.steps = n;
    const SceneRunResult all = run_scene(req);
    double rebuild_sum = 0, listed_sum = 0;
    long rebuilds = 0;
    for (const auto& s : all.steps) {
        const bool rebuilt = s.step > 1 && (s.step - 1) % 3 == 0;
        (rebuilt ? rebuild_sum : listed_sum) += s.wall_ms;
        rebuilds += rebuilt;
    }
    EXPECT_EQ(all.cost.rebuild_steps, rebuilds);
    EXPECT_NEAR(all.cost.rebuild_step_ms(), rebuild_sum / double(rebuilds), 1e-9);
    EXPECT_NEAR(all.cost.listed_step_ms(), listed_sum / double(n - rebuilds), 1e-9);
    // Without lists no step rebuilds; the means of rebuild steps are then NaN.
    req.solver.search.verlet = false;
    const SceneRunResult cells = run_scene(req);
    EXPECT_EQ(cells.cost.rebuild_steps, 0);
    EXPECT_TRUE(std::isnan(cells.cost.rebuild_step_ms()));
}

TEST_F(WholeRunTest, SimulateRunsAnySceneToAnEndTimeAndReportsSecondsPerSimulatedSecond) {
    const std::vector<double> t = step_times(5);
    const std::string end = format_number(0.5 * (t[3] + t[4]));
    testing::internal::CaptureStdout();
    const int code = sphbench({"simulate", "dsph-dambreak", "--set", "dp=0.05", "--end-time", end, "--warmup", "1",
                               "--backend", "host", "--quiet", "--verlet", "--out", (dir_ / "sim").string()});
    const std::string out = testing::internal::GetCapturedStdout();
    ASSERT_EQ(code, exit_ok) << out;
    EXPECT_NE(out.find("run: 5 steps (1 of them warm-up)"), std::string::npos) << out;
    EXPECT_NE(out.find("stopped at the end time "), std::string::npos) << out;
    EXPECT_NE(out.find("s per simulated second"), std::string::npos) << out;
    EXPECT_NE(out.find("Verlet lists: "), std::string::npos) << out;
    EXPECT_NE(out.find("bytes per particle"), std::string::npos) << out;
    // --steps caps it, and the summary says the cap stopped it.
    testing::internal::CaptureStdout();
    ASSERT_EQ(sphbench({"simulate", "dsph-dambreak", "--set", "dp=0.05", "--end-time", "10", "--steps", "2",
                        "--warmup", "1", "--backend", "host", "--quiet", "--out", (dir_ / "sim").string()}),
              exit_ok);
    const std::string capped = testing::internal::GetCapturedStdout();
    EXPECT_NE(capped.find("run: 3 steps"), std::string::npos) << capped;
    EXPECT_NE(capped.find("stopped by the step cap"), std::string::npos) << capped;
    // --validate with an end time works as before (the dam break of Martin and Moyce has a metric).
    testing::internal::CaptureStdout();
    EXPECT_EQ(sphbench({"simulate", "dambreak", "--set", "dp=0.05", "--validate", "0.01", "--end-time", "0.02",
                        "--warmup", "0", "--backend", "host", "--quiet", "--out", (dir_ / "val").string()}),
              exit_ok);
    const std::string validated = testing::internal::GetCapturedStdout();
    EXPECT_NE(validated.find("stopped at the end time 0.02 s"), std::string::npos) << validated;
    EXPECT_NE(validated.find("validation: "), std::string::npos) << validated;
}

TEST_F(WholeRunTest, RunsCsvCarriesTheWholeRun) {
    const std::vector<double> t = step_times(8);
    const std::string end = format_number(0.5 * (t[5] + t[6]));
    const std::string spec = write("whole.toml", "name = \"whole\"\nreproduces = \"a test\"\nend_time = " + end +
                                                     "\nrecord = [\"summary\", \"steps\"]\n[solver]\nbackend = \"host\"\n"
                                                     "[[runs]]\nscene = \"dsph-dambreak\"\nlabel = \"vl\"\n"
                                                     "set = { dp = 0.05 }\nsolver = { verlet = true, rebuild_every = 2 }\n"
                                                     "[[runs]]\nscene = \"dsph-dambreak\"\nlabel = \"cells\"\n"
                                                     "set = { dp = 0.05 }\n");
    const std::string out = (dir_ / "out").string();
    ASSERT_EQ(sphbench({"run", spec, "--out", out, "--quiet"}), exit_ok);
    const CsvTable runs = read_csv(out + "/whole/runs.csv");
    ASSERT_EQ(runs.rows.size(), 2u);
    ASSERT_TRUE(runs.meta("columns").has_value());
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(runs.cell(i, "end_time"), end);
        EXPECT_EQ(runs.cell(i, "steps"), "7");
        EXPECT_EQ(runs.cell(i, "window_steps"), "7");  // warm-up 0: the whole event counts
        EXPECT_EQ(runs.cell(i, "stopped_by"), "end_time");
        // The lists sum the same pairs in another order: the time steps agree to rounding.
        EXPECT_NEAR(std::stod(runs.cell(i, "sim_time")), t[6], 1e-6 * t[6]);
        const double wall = std::stod(runs.cell(i, "wall_s")), sim = std::stod(runs.cell(i, "sim_time"));
        EXPECT_DOUBLE_EQ(std::stod(runs.cell(i, "s_per_sim_s")), wall / sim);
        EXPECT_NE(runs.cell(i, "neighbours_per_step"), "") << "the work counters, on the state the run ends with";
    }
    const std::size_t vl = runs.cell(0, "run_id") == "vl" ? 0 : 1, cells = 1 - vl;
    EXPECT_EQ(runs.cell(vl, "list_rebuilds"), "3");  // steps 3, 5 and 7
    const CsvTable steps = read_csv(out + "/whole/vl_steps.csv");
    double rebuild = 0, listed = 0;
    for (const auto& row : steps.rows) {
        const long step = std::stol(row[std::size_t(steps.column("step"))]);
        const double ms = std::stod(row[std::size_t(steps.column("wall_ms"))]);
        (step > 1 && (step - 1) % 2 == 0 ? rebuild : listed) += ms;
    }
    EXPECT_NEAR(std::stod(runs.cell(vl, "rebuild_step_ms")), rebuild / 3, 1e-6 * rebuild);
    EXPECT_NEAR(std::stod(runs.cell(vl, "listed_step_ms")), listed / 4, 1e-6 * listed);
    EXPECT_GT(std::stod(runs.cell(vl, "list_bytes_per_particle")), 0);
    for (const char* column : {"list_rebuilds", "rebuild_step_ms", "listed_step_ms", "list_bytes_per_particle"})
        EXPECT_EQ(runs.cell(cells, column), "") << column << ": no lists";

    // `--end-time` on `run` is `--set end_time`; the spec's steps then cap.
    const std::string capped = write("capped.toml", "name = \"capped\"\nreproduces = \"a test\"\nsteps = 3\nwarmup = 1\n"
                                                     "[solver]\nbackend = \"host\"\n[[runs]]\nscene = \"dsph-dambreak\"\n"
                                                     "set = { dp = 0.05 }\n");
    ASSERT_EQ(sphbench({"run", capped, "--out", out, "--quiet", "--end-time", format_number(t[1])}), exit_ok);
    const CsvTable c = read_csv(out + "/capped/runs.csv");
    EXPECT_EQ(c.cell(0, "steps"), "2");
    EXPECT_EQ(c.cell(0, "window_steps"), "1");
    EXPECT_EQ(c.cell(0, "stopped_by"), "end_time");
    ASSERT_EQ(sphbench({"run", capped, "--out", out, "--quiet", "--force", "--end-time", "10"}), exit_ok);
    const CsvTable c2 = read_csv(out + "/capped/runs.csv");
    EXPECT_EQ(c2.cell(0, "steps"), "4");
    EXPECT_EQ(c2.cell(0, "stopped_by"), "steps");
    EXPECT_EQ(number(c2, "end_time"), 10);
}

TEST_F(WholeRunTest, StabilityStudiesTakeAnEndTime) {
    const std::vector<double> t = step_times(4);
    const std::string spec = write("energy.toml", "name = \"energy\"\nreproduces = \"a test\"\nend_time = " +
                                                      format_number(t[3]) +
                                                      "\n[solver]\nbackend = \"host\"\n[stability]\nprobe = \"energy\"\n"
                                                      "sample_every = 2\n[[runs]]\nscene = \"dsph-dambreak\"\n"
                                                      "set = { dp = 0.05 }\n");
    const std::string out = (dir_ / "out").string();
    testing::internal::CaptureStdout();
    const int code = sphbench({"stability", spec, "--out", out, "--quiet"});
    testing::internal::GetCapturedStdout();
    ASSERT_EQ(code, exit_ok);
    const CsvTable s = read_csv(out + "/energy/summary.csv");
    EXPECT_EQ(s.cell(0, "steps"), "4");
    EXPECT_EQ(std::stod(s.cell(0, "time")), t[3]);
    // --end-time overrides it.
    testing::internal::CaptureStdout();
    ASSERT_EQ(sphbench({"stability", spec, "--out", out, "--quiet", "--end-time", format_number(t[1])}), exit_ok);
    testing::internal::GetCapturedStdout();
    EXPECT_EQ(read_csv(out + "/energy/summary.csv").cell(0, "steps"), "2");
    // Both the top level's end_time and [stability] time: refused, naming both.
    const std::string both = write("both.toml", "name = \"both\"\nreproduces = \"a test\"\nend_time = 0.1\n"
                                                "[stability]\nprobe = \"energy\"\ntime = 0.2\n[[runs]]\nscene = \"tank\"\n");
    std::string m;
    EXPECT_EQ(sphbench({"stability", both, "--out", out}, m), exit_usage);
    EXPECT_NE(m.find("end_time"), std::string::npos) << m;
    EXPECT_NE(m.find("time"), std::string::npos) << m;
}

TEST_F(WholeRunTest, BadEndTimesAreRefusedInOneSentence) {
    const std::string good = write("good.toml", "name = \"g\"\nreproduces = \"a test\"\nsteps = 1\n[[runs]]\nscene = \"tank\"\n");
    const std::string text = write("text.toml", "name = \"t\"\nreproduces = \"a test\"\nend_time = \"x\"\n[[runs]]\nscene = \"tank\"\n");
    const std::string negative = write("neg.toml", "name = \"n\"\nreproduces = \"a test\"\nend_time = -1\n[[runs]]\nscene = \"tank\"\n");
    struct Case {
        std::vector<std::string> args;
        std::string expected;
    };
    const std::string range = "(allowed: a number greater than 0)";
    const std::vector<Case> cases = {
        {{"simulate", "tank", "--end-time", "-1"}, "--end-time: -1 is out of range " + range},
        {{"simulate", "tank", "--end-time", "x"}, "--end-time: 'x' is not a number " + range},
        {{"simulate", "tank", "--end-time", "0"}, "--end-time: 0 is out of range " + range},
        {{"run", good, "--end-time", "-1"}, "--end-time: -1 is out of range " + range},
        {{"run", good, "--set", "end_time=x"}, "--set end_time: 'x' is not a number " + range},
        {{"run", text}, text + ":3: 'end_time' must be a number, not a string"},
        {{"run", negative}, negative + ":3: end_time: -1 is out of range " + range},
    };
    for (const Case& c : cases) {
        std::string m;
        EXPECT_EQ(sphbench(c.args, m), exit_usage) << c.args[0] << " " << c.args[2];
        EXPECT_EQ(m, c.expected);
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    // A spec without steps needs an end time.
    const std::string neither = write("neither.toml", "name = \"n\"\nreproduces = \"a test\"\n[[runs]]\nscene = \"tank\"\n");
    std::string m;
    EXPECT_EQ(sphbench({"run", neither}, m), exit_usage);
    EXPECT_NE(m.find("steps"), std::string::npos) << m;
}

}  // namespace
}  // namespace sph

namespace sph {
namespace {

class RunOwnStepsTest : public test::ScratchFolderTest {
protected:
    RunOwnStepsTest() : ScratchFolderTest("sph_run_own_steps_") {}
};

// whole-run.toml's shape: runs to their own end times and one of its own steps; --set end_time
// and --set steps replace them in every run.
TEST_F(RunOwnStepsTest, ARunsOwnStepsAndEndTimeReplaceTheSpecsAndSetReplacesThem) {
    const std::string path = (dir_ / "own.toml").string();
    std::ofstream(path) << "name = \"own\"\nreproduces = \"a test\"\nsteps = 50\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"a\"\nend_time = 0.3\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"b\"\nsteps = 7\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"c\"\n";
    const ExperimentSpec spec = load_spec(path);
    std::vector<PlannedRun> runs = expand(spec, ExpandOptions{});
    ASSERT_EQ(runs.size(), 3u);
    EXPECT_EQ(runs[0].end_time, 0.3);
    EXPECT_EQ(runs[0].steps, 50);  // the spec's steps: a cap of this run
    EXPECT_EQ(runs[1].end_time, 0);
    EXPECT_EQ(runs[1].steps, 7);
    EXPECT_EQ(runs[2].steps, 50);
    ExpandOptions over;
    over.overrides = {{"end_time", "0.05"}, {"steps", "9"}};
    runs = expand(spec, over);
    for (const auto& r : runs) {
        EXPECT_EQ(r.end_time, 0.05) << r.run_id;
        EXPECT_EQ(r.steps, 9) << r.run_id;
    }
    // Without top-level steps every run needs its own steps or end time.
    std::ofstream(path) << "name = \"own\"\nreproduces = \"a test\"\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"a\"\nend_time = 0.3\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"b\"\n";
    try {
        load_spec(path);
        ADD_FAILURE() << "a run without steps or end time was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("line 7"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace sph
