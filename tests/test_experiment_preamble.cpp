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

}  // namespace
}  // namespace sph
