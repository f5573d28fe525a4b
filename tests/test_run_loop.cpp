// The one run loop of `run`, `simulate` and `stability` (harness/run_loop.hpp): its stop
// rules stop at the right step, its sinks see the warm-up, the last step and a blow-up as
// they should, the step table's columns come from one declaration, the derived per-step
// figures are the step record's, and `run_scene` and the stability trial step alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "column_table.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "end_time_stop.hpp"
#include "io/csv_writer.hpp"
#include "record_blow_up.hpp"
#include "run_loop.hpp"
#include "scene_run.hpp"
#include "scratch_folder.hpp"
#include "stability_probe.hpp"
#include "step_count_stop.hpp"
#include "step_recorder.hpp"
#include "step_table.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace sph {
namespace {

const std::map<std::string, std::string> dambreak_options = {
    {"dp", "0.05"}, {"length", "1.0"}, {"column_height", "0.6"}, {"height", "0.8"}};

// Every point the loop reports, for checking what sinks are told.
class PointLog final : public StepSink {
public:
    void begin(Simulation& sim) override { begun_at = sim.steps_taken(), begins++; }
    void after_step(Simulation&, const StepRecord& r, const StepPoint& at) override {
        points.push_back(at);
        times.push_back(r.time);
    }
    void blow_up(const BlowUpError& e, std::string& where) override {
        blown_at = e.step;
        where += "; noted by the log";
    }
    void end(Simulation&) override { ends++; }
    std::vector<StepPoint> points;
    std::vector<double> times;
    int begins = 0, ends = 0;
    long begun_at = -1, blown_at = 0;
};

// Times after each of the first n steps of the small dam break.
std::vector<double> step_times(const Scene& s, long n) {
    Simulation sim(s, SolverOptions{});
    RunLoop loop(sim);
    StepCountStop budget(n);
    PointLog log;
    loop.stop_when(budget).feed(log);
    loop.run();
    return log.times;
}

TEST(RunLoop, StepCountStopsAfterItsStepsAndMarksTheLastOne) {
    const Scene s = test::small_dambreak("0.05");
    Simulation sim(s, SolverOptions{});
    RunLoop loop(sim, 3);
    StepCountStop budget(8);
    PointLog log;
    StepRecorder recorded;
    loop.stop_when(budget).feed(log).feed(recorded);
    const RunLoopOutcome out = loop.run();
    EXPECT_EQ(out.steps, 8);
    EXPECT_FALSE(out.blow_up);
    EXPECT_EQ(log.begins, 1);
    EXPECT_EQ(log.begun_at, 0);
    EXPECT_EQ(log.ends, 1);
    ASSERT_EQ(log.points.size(), 8u);
    for (std::size_t k = 0; k < 8; ++k) {
        EXPECT_EQ(log.points[k].step, long(k) + 1);
        EXPECT_EQ(log.points[k].recorded, k >= 3) << k;  // three warm-up steps
        EXPECT_EQ(log.points[k].recorded_step, long(k) + 1 - 3);
        EXPECT_EQ(log.points[k].last, k == 7) << k;
    }
    ASSERT_EQ(recorded.records().size(), 5u);
    EXPECT_EQ(recorded.records().front().step, 4);
    EXPECT_EQ(recorded.records().back().step, 8);
}

TEST(RunLoop, EndTimeStopsAtTheFirstStepThatReachesIt) {
    const Scene s = test::small_dambreak("0.05");
    const std::vector<double> t = step_times(s, 12);
    ASSERT_EQ(t.size(), 12u);
    // Exactly a step's time: that step is the last; a hair past it: the next one.
    for (std::size_t k : {std::size_t(0), std::size_t(4), std::size_t(9)}) {
        for (const bool past : {false, true}) {
            Simulation sim(s, SolverOptions{});
            RunLoop loop(sim);
            EndTimeStop end(past ? std::nextafter(t[k], 1.0) : t[k]);
            StepCountStop cap(100);
            PointLog log;
            loop.stop_when(end).stop_when(cap).feed(log);
            const RunLoopOutcome out = loop.run();
            const long expected = long(k) + (past ? 2 : 1);
            EXPECT_EQ(out.steps, expected) << "end time " << end.end_time();
            EXPECT_EQ(out.time, t[std::size_t(expected) - 1]);
            ASSERT_FALSE(log.points.empty());
            EXPECT_TRUE(log.points.back().last);
            for (std::size_t i = 0; i + 1 < log.points.size(); ++i) EXPECT_FALSE(log.points[i].last);
        }
    }
}

TEST(RunLoop, AStepBudgetBehindAnEndTimeRefusesOnlyWhenTheTimeIsOutOfReach) {
    const Scene s = test::small_dambreak("0.05");
    const std::vector<double> t = step_times(s, 5);
    auto run = [&](double end_time) {
        Simulation sim(s, SolverOptions{});
        RunLoop loop(sim);
        EndTimeStop end(end_time);
        StepCountStop cap(5, [](const Simulation& at) { return "only t = " + std::to_string(at.time()); });
        loop.stop_when(end).stop_when(cap);
        return loop.run().steps;
    };
    EXPECT_EQ(run(t[4]), 5);  // reached on the budget's last step: the end time is asked first
    try {
        run(std::nextafter(t[4], 1.0));
        FAIL() << "a time past the budget must be refused";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("only t = "), std::string::npos) << e.what();
    }
    // A budget of no steps is refused before any step.
    Simulation sim(s, SolverOptions{});
    RunLoop loop(sim);
    EndTimeStop end(1.0);
    StepCountStop none(0, [](const Simulation&) { return std::string("no steps"); });
    loop.stop_when(end).stop_when(none);
    EXPECT_THROW(loop.run(), InputError);
    EXPECT_EQ(sim.steps_taken(), 0);
}

// An absurd CFL number blows the small dam break up within a few dozen steps.
SolverOptions absurd_cfl() {
    SolverOptions o;
    o.cfl = 4.0;
    return o;
}

TEST(RunLoop, ABlowUpFailsTheRunUnlessARuleRecordsIt) {
    const Scene s = test::small_dambreak("0.05");
    {
        Simulation sim(s, absurd_cfl());
        RunLoop loop(sim);
        StepCountStop budget(500);
        loop.stop_when(budget);
        EXPECT_THROW(loop.run(), BlowUpError);  // no sink said where a state went: the blow-up itself
    }
    {
        Simulation sim(s, absurd_cfl());
        RunLoop loop(sim);
        StepCountStop budget(500);
        PointLog log;
        loop.stop_when(budget).feed(log);
        try {
            loop.run();
            FAIL() << "cfl = 4 should blow up";
        } catch (const BlowUpError&) {
            FAIL() << "a sink noted where: the run fails with a RunError that says so";
        } catch (const RunError& e) {
            EXPECT_NE(std::string(e.what()).find("; noted by the log"), std::string::npos) << e.what();
        }
        EXPECT_EQ(log.ends, 0);  // a failed run has no end
    }
    Simulation sim(s, absurd_cfl());
    RunLoop loop(sim);
    StepCountStop budget(500);
    RecordBlowUp record;
    PointLog log;
    loop.stop_when(budget).stop_when(record).feed(log);
    const RunLoopOutcome out = loop.run();
    ASSERT_TRUE(out.blow_up);
    EXPECT_EQ(out.blow_up->step, out.steps + 1);
    EXPECT_EQ(out.blow_up->step, log.blown_at);
    EXPECT_EQ(out.blow_up->where, "; noted by the log");
    EXPECT_NE(out.blow_up->message.find("blew up at step " + std::to_string(out.blow_up->step)), std::string::npos);
    EXPECT_FALSE(out.blow_up->quantity.empty());
    EXPECT_EQ(log.ends, 1);  // a recorded blow-up ends the run: the sinks finish
    EXPECT_EQ(long(log.points.size()), out.steps);
}

TEST(RunLoop, RunSceneAndTheStabilityTrialStepAlike) {
    const long n = 15;
    SceneRunRequest req;
    req.scene = "dambreak";
    req.scene_options = dambreak_options;
    req.steps = n;
    req.progress = false;
    const SceneRunResult run = run_scene(req);
    ASSERT_EQ(run.steps.size(), std::size_t(n));

    const Scene s = make_scene("dambreak", dambreak_options);
    StepRecorder trial_steps;
    const TrialOutcome fixed = run_trial(s, SolverOptions{}, TrialTarget{0, n, false}, {&trial_steps});
    EXPECT_TRUE(fixed.stable);
    EXPECT_EQ(fixed.steps, n);
    ASSERT_EQ(trial_steps.records().size(), std::size_t(n));
    for (long k = 0; k < n; ++k) {
        const StepRecord &a = run.steps[std::size_t(k)], &b = trial_steps.records()[std::size_t(k)];
        EXPECT_EQ(a.step, b.step);
        EXPECT_EQ(a.time, b.time) << "step " << a.step;
        EXPECT_EQ(a.dt, b.dt);
        EXPECT_EQ(a.stats.kinetic_energy, b.stats.kinetic_energy);
        EXPECT_EQ(a.stats.max_speed2, b.stats.max_speed2);
        EXPECT_EQ(a.stats.min_density, b.stats.min_density);
        EXPECT_EQ(a.stats.max_density, b.stats.max_density);
        EXPECT_EQ(a.stats.fluid_count, b.stats.fluid_count);
    }
    // A trial to a simulated time ends where run_scene's record reached it.
    const TrialOutcome timed = run_trial(s, SolverOptions{}, TrialTarget{run.steps[9].time, 100, false});
    EXPECT_EQ(timed.steps, 10);
    EXPECT_EQ(timed.time, run.steps[9].time);
}

TEST(StepRecordFigures, StepUpdateAndIdealComeFromThePhaseTimes) {
    StepRecord r;
    r.phase_ms = {1, 2, 3, 4, 5, 6, 7};
    EXPECT_EQ(r.step_ms(), 28.0);
    EXPECT_EQ(r.update_ms(), 5.0);  // forces + integrate, no subdomain times
    EXPECT_EQ(r.update_ideal_ms(), 5.0);
    PhaseTimes fast{}, slow{};
    fast[std::size_t(Phase::forces)] = 1, fast[std::size_t(Phase::integrate)] = 1;
    slow[std::size_t(Phase::forces)] = 5, slow[std::size_t(Phase::integrate)] = 1;
    r.subdomain_ms = {fast, slow};
    EXPECT_EQ(r.update_ms(), 6.0);        // the slowest subdomain's: the paper's real time
    EXPECT_EQ(r.update_ideal_ms(), 4.0);  // their mean
}

class StepTableTest : public test::ScratchFolderTest {
protected:
    StepTableTest() : ScratchFolderTest("sph_test_step_table_") {}
};

TEST_F(StepTableTest, TheStepCsvIsWrittenFromTheOneDeclarationWithTheColumnsItAlwaysHad) {
    // The layout readers (plots/, compare) rely on: names and order (transfer_ms last, added
    // with the overlap of paper 5.3).
    const std::vector<std::string> expected = {
        "step", "time", "dt", "fluid", "boundary", "out_of_domain", "kinetic_energy", "max_speed", "min_density",
        "max_density", "neighbour_list_ms", "forces_ms", "integrate_ms", "diagnostics_ms", "exchange_ms",
        "migrate_ms", "balance_ms", "update_ms", "update_ideal_ms", "step_ms", "wall_ms", "subdomains",
        "slices_moved", "particles_migrated", "ghosts_sent", "bytes_exchanged", "subdomain_update_ms",
        "subdomain_particles", "transfer_ms"};
    EXPECT_EQ(step_csv_columns(), expected);

    SceneRunRequest req;
    req.scene = "dambreak";
    req.scene_options = dambreak_options;
    req.solver.subdomains = 2;
    req.steps = 4;
    req.warmup = 1;
    req.progress = false;
    req.out_dir = dir_.string();
    req.basename = "table";
    const SceneRunResult res = run_scene(req);
    const CsvTable t = read_csv((dir_ / "table_steps.csv").string());
    EXPECT_EQ(t.columns, expected);
    ASSERT_EQ(t.rows.size(), res.steps.size());
    for (std::size_t i = 0; i < t.rows.size(); ++i) {
        const StepRecord& r = res.steps[i];
        EXPECT_EQ(t.rows[i], step_csv_row(r, res.boundary));
        EXPECT_EQ(t.cell(i, "step"), std::to_string(r.step));
        EXPECT_EQ(t.cell(i, "boundary"), std::to_string(res.boundary));
        EXPECT_EQ(t.cell(i, "step_ms"), CsvWriter::fmt(r.step_ms()));
        EXPECT_EQ(t.cell(i, "update_ms"), CsvWriter::fmt(r.update_ms()));
        EXPECT_EQ(t.cell(i, "update_ideal_ms"), CsvWriter::fmt(r.update_ideal_ms()));
        EXPECT_EQ(t.cell(i, "subdomains"), "2");
        EXPECT_EQ(std::count(t.cell(i, "subdomain_particles").begin(), t.cell(i, "subdomain_particles").end(), ';'), 1);
    }
    EXPECT_EQ(t.cell(0, "step"), "2");  // the warm-up step is not recorded
}

TEST(ColumnTable, NamesAndCellsComeFromTheSameEntries) {
    struct Row {
        int a;
        std::string b;
    };
    ColumnTable<Row> t;
    t.add("a", [](const Row& r) { return std::to_string(r.a); }).add("b", [](const Row& r) { return r.b; });
    ColumnTable<std::pair<Row, int>> wider;
    wider.append(t, [](const std::pair<Row, int>& p) { return p.first; })
        .add("c", [](const std::pair<Row, int>& p) { return std::to_string(p.second); });
    EXPECT_EQ(wider.names(), (std::vector<std::string>{"a", "b", "c"}));
    EXPECT_EQ(wider.cells({Row{1, "x"}, 3}), (std::vector<std::string>{"1", "x", "3"}));
    EXPECT_EQ(wider.size(), 3u);
}

}  // namespace
}  // namespace sph
