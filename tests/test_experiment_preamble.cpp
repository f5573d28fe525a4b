// The preamble `run` and `stability` share (harness/experiment_preamble.hpp): each refuses the
// other's specs, --only is checked against the expanded runs, and both write the same
// provenance keys in the same order, which is what the freshness check compares.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "experiment_preamble.hpp"
#include "experiment_runner.hpp"
#include "validation/validation_metric.hpp"
#include "scratch_folder.hpp"

namespace sph {
namespace {

class PreambleTest : public test::ScratchFolderTest {
protected:
    PreambleTest() : ScratchFolderTest("sph_test_preamble_") {}
    std::string write(const std::string& name, const std::string& extra) {
        const std::string path = (dir_ / name).string();
        std::ofstream(path) << "name = \"" << name.substr(0, name.find('.')) << "\"\nreproduces = \"t\"\nsteps = 5\n"
                            << "[[runs]]\nscene = \"tank\"\nlabel = \"a\"\n[[runs]]\nscene = \"tank\"\nlabel = \"b\"\n"
                            << extra;
        return path;
    }
    ExperimentArgs args(const std::string& spec) {
        ExperimentArgs a;
        a.spec = spec;
        a.out = (dir_ / "out").string();
        a.backend = "host";
        return a;
    }
};

std::vector<std::string> keys(const Metadata& m) {
    std::vector<std::string> k;
    for (const auto& [key, value] : m) k.push_back(key);
    return k;
}

TEST_F(PreambleTest, EachCommandRefusesTheOthersSpecs) {
    const std::string runs = write("runs.toml", ""), study = write("study.toml", "[stability]\nprobe = \"energy\"\n");
    EXPECT_NO_THROW(load_experiment(args(runs), ExperimentKind::runs));
    EXPECT_NO_THROW(load_experiment(args(study), ExperimentKind::stability));
    try {
        load_experiment(args(study), ExperimentKind::runs);
        FAIL() << "run must refuse a stability spec";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sphbench stability"), std::string::npos) << e.what();
    }
    try {
        load_experiment(args(runs), ExperimentKind::stability);
        FAIL() << "stability must refuse a spec without [stability]";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("no [stability] table"), std::string::npos) << e.what();
    }
}

TEST_F(PreambleTest, OnlyAndOverridesAreAppliedAndWrittenOnce) {
    ExperimentArgs a = args(write("runs.toml", ""));
    a.only = {"b"};
    a.settings = {"steps=3"};
    const Experiment e = load_experiment(a, ExperimentKind::runs);
    ASSERT_EQ(e.runs.size(), 1u);
    EXPECT_EQ(e.runs[0].run_id, "b");
    EXPECT_EQ(e.runs[0].steps, 3);
    EXPECT_EQ(e.backend, "host");
    EXPECT_EQ(e.dir, (dir_ / "out" / "runs").string());
    EXPECT_EQ(overrides_text(a), "--set steps=3 --backend host --only b");
    EXPECT_EQ(override_arguments(a), (std::vector<std::string>{"--set", "steps=3", "--backend", "host"}));
    a.only = {"c"};
    EXPECT_THROW(load_experiment(a, ExperimentKind::runs), InputError);
    EXPECT_EQ(overrides_text(args("x.toml")).find("--only"), std::string::npos);
    ExperimentArgs none;
    EXPECT_EQ(overrides_text(none), "none");
}

TEST_F(PreambleTest, RunAndStabilityWriteTheSameProvenanceKeys) {
    char name[] = "sphbench";
    char* argv[] = {name};
    const CommandContext ctx{1, argv};
    const ExperimentArgs r = args(write("runs.toml", "")), s = args(write("study.toml", "[stability]\nprobe = \"energy\"\n"));
    const Metadata from_run = experiment_metadata(load_experiment(r, ExperimentKind::runs), r, ctx);
    const Metadata from_study = experiment_metadata(load_experiment(s, ExperimentKind::stability), s, ctx);
    EXPECT_EQ(keys(from_run), keys(from_study));
    const std::vector<std::string> k = keys(from_run);
    for (const char* key : {"spec_hash", "binary_hash", "overrides", "backend", "experiment", "scale", "reduced_scale"})
        EXPECT_NE(std::find(k.begin(), k.end(), key), k.end()) << key;
}

// runs.csv from its one declaration: every row as wide as the header, and the cells that the
// old name-keyed layout filled (settings, sizes, summaries, validation only where asked).
TEST_F(PreambleTest, RunsTableCellsComeFromTheirColumns) {
    const std::string path = write("table.toml", "");
    std::ofstream(path, std::ios::app) << "[[runs]]\nscene = \"tank\"\nlabel = \"v\"\nset = { dp = 0.05 }\n"
                                       << "validation = { every = 0.01, end_time = 0.02 }\n";
    const std::vector<PlannedRun> runs = load_experiment(args(path), ExperimentKind::runs).runs;
    ASSERT_EQ(runs.size(), 3u);
    const ColumnTable<RunsRow> table = runs_table(runs);
    const std::vector<std::string> names = table.names();
    EXPECT_EQ(names, runs_csv_columns(runs));
    const ValidationMetricInfo* tank = find_validation_metric("tank");
    ASSERT_NE(tank, nullptr);
    SceneRunResult r;
    r.device = "host";
    r.particles = 100;
    for (int k = 0; k < 3; ++k) {
        StepRecord s;
        s.step = k + 1;
        s.time = 0.01 * (k + 1);
        s.phase_ms[std::size_t(Phase::forces)] = 1.0 + k;
        s.subdomain_ms = {s.phase_ms};
        r.steps.push_back(s);
    }
    r.steps_taken = 3;
    r.sim_time = r.steps.back().time;
    r.wall_seconds = 0.6;
    for (const auto& c : tank->summary_columns) r.validation_summary.emplace_back(c, 0.5);
    auto cell = [&](const PlannedRun& run, const std::string& column) {
        const std::vector<std::string> cells = table.cells(RunsRow(run, r, "x_steps.csv"));
        EXPECT_EQ(cells.size(), names.size());
        const auto at = std::find(names.begin(), names.end(), column);
        return at == names.end() ? std::string("<no column>") : cells[std::size_t(at - names.begin())];
    };
    EXPECT_EQ(cell(runs[0], "run_id"), "a");
    EXPECT_EQ(cell(runs[0], "backend"), "host");
    EXPECT_EQ(cell(runs[0], "forces_ms_median"), "2");
    EXPECT_EQ(cell(runs[0], "step_ms_min"), "1");
    EXPECT_EQ(cell(runs[0], "sim_time"), "0.03");
    EXPECT_EQ(cell(runs[0], "steps"), "3");
    EXPECT_EQ(cell(runs[0], "window_steps"), "3");
    EXPECT_EQ(cell(runs[0], "s_per_sim_s"), format_number(0.6 / 0.03));
    EXPECT_EQ(cell(runs[0], "end_time"), "");          // no end time asked
    EXPECT_EQ(cell(runs[2], "end_time"), "0.02");      // its validation's end time is the run's
    EXPECT_EQ(cell(runs[0], "list_rebuilds"), "");     // no Verlet lists
    EXPECT_EQ(cell(runs[0], "set.dp"), "");  // another run's option
    EXPECT_EQ(cell(runs[2], "set.dp"), "0.05");
    EXPECT_EQ(cell(runs[0], "steps_file"), "x_steps.csv");
    EXPECT_EQ(cell(runs[0], "blow_up"), "<no column>");  // no run records blow-ups
    EXPECT_EQ(cell(runs[0], tank->summary_columns.front()), "");  // no validation asked
    EXPECT_EQ(cell(runs[2], tank->summary_columns.front()), "0.5");
    EXPECT_EQ(cell(runs[2], "steps_run"), "3");
    EXPECT_EQ(cell(runs[2], "validation_every"), "0.01");
}

}  // namespace
}  // namespace sph
