// Experiment specs: a valid spec expands to the right runs with stable ids; every kind of bad
// input is refused with the file, the line and the key; overrides and the host scale apply.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scratch_folder.hpp"
#include "core/error.hpp"
#include "experiment_spec.hpp"

namespace fs = std::filesystem;

namespace sph {
namespace {

class SpecTest : public test::ScratchFolderTest {
protected:
    SpecTest() : ScratchFolderTest("sph_test_spec_") {}

    std::string write(const std::string& text, const std::string& name = "spec.toml") {
        const std::string path = (dir_ / name).string();
        std::ofstream(path) << text;
        return path;
    }

    // The message of the InputError that loading `text` throws ("" if none).
    std::string error_of(const std::string& text) {
        const std::string path = write(text, "bad.toml");
        try {
            load_spec(path);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }

};

const char* valid_spec = R"(name = "sweepy"
reproduces = "a test"
steps = 10
warmup = 2
repetitions = 2
record = ["summary", "steps"]

[solver]
merge = true

[[runs]]
scene = "tank"
label = "small tank"
set = { dp = 0.05 }

[[runs]]
scene = "dambreak"
set = { particles = 4000 }
solver = { merge = false }

[sweep]
cells_per_support = [1, 2]
set.layers = [2, 3]

[host]
scale = 0.5
steps = 4
)";

TEST_F(SpecTest, ValidSpecExpandsToTheCartesianProductWithStableIds) {
    const ExperimentSpec spec = load_spec(write(valid_spec));
    EXPECT_EQ(spec.name, "sweepy");
    EXPECT_EQ(spec.runs.size(), 2u);
    EXPECT_TRUE(spec.records("steps"));
    ExpandOptions opt;
    opt.gpu_available = true;  // CUDA: no host reduction
    const auto runs = expand(spec, opt);
    ASSERT_EQ(runs.size(), 2u * 2u * 2u * 2u);  // runs x cells_per_support x layers x repetitions
    EXPECT_EQ(runs[0].run_id, "small-tank_cells_per_support-1_layers-2_rep1");
    EXPECT_EQ(runs[0].config, "small-tank_cells_per_support-1_layers-2");
    EXPECT_EQ(runs[1].run_id, "small-tank_cells_per_support-1_layers-2_rep2");
    EXPECT_EQ(runs[1].repetition, 2);
    EXPECT_EQ(runs[2].run_id, "small-tank_cells_per_support-1_layers-3_rep1");
    EXPECT_EQ(runs[8].run_id, "dambreak-2_cells_per_support-1_layers-2_rep1");
    EXPECT_EQ(runs[15].run_id, "dambreak-2_cells_per_support-2_layers-3_rep2");
    EXPECT_EQ(runs[4].solver.search.cells_per_support, 2);
    EXPECT_TRUE(runs[0].solver.search.merge);   // [solver] default
    EXPECT_FALSE(runs[8].solver.search.merge);  // per-run override
    EXPECT_EQ(runs[2].scene_options.at("layers"), "3");
    EXPECT_EQ(runs[0].scene_options.at("dp"), "0.05");
    EXPECT_EQ(runs[0].steps, 10);
    EXPECT_EQ(runs[0].warmup, 2);
    EXPECT_FALSE(runs[0].reduced_scale);
    EXPECT_EQ(runs[0].solver.backend, BackendKind::cuda);
    EXPECT_EQ(runs[0].solver_settings.at("verlet"), "false");  // every key has a column value
    // Expanding again gives the same ids in the same order.
    const auto again = expand(load_spec(write(valid_spec)), opt);
    for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(again[i].run_id, runs[i].run_id);
}

TEST_F(SpecTest, HostBackendAppliesTheReducedScaleOfHostSection) {
    const ExperimentSpec spec = load_spec(write(valid_spec));
    ExpandOptions opt;  // no GPU: auto resolves to the host
    const auto runs = expand(spec, opt);
    EXPECT_EQ(runs[0].solver.backend, BackendKind::host);
    EXPECT_TRUE(runs[0].reduced_scale);
    EXPECT_EQ(runs[0].steps, 4);
    EXPECT_DOUBLE_EQ(runs[0].scale, 0.5);
    EXPECT_EQ(runs[8].scene_options.at("particles"), "2000");
    EXPECT_NEAR(std::stod(runs[0].scene_options.at("dp")), 0.05 / std::cbrt(0.5), 1e-12);
    opt.scale = 0.5;  // --scale multiplies on top
    EXPECT_EQ(expand(spec, opt)[8].scene_options.at("particles"), "1000");
    opt.backend = "cuda";  // asked for CUDA: full scale, whatever the machine
    opt.scale = 1.0;
    const auto gpu = expand(spec, opt);
    EXPECT_FALSE(gpu[0].reduced_scale);
    EXPECT_EQ(gpu[8].scene_options.at("particles"), "4000");
}

TEST_F(SpecTest, SetOverridesReplaceSpecValuesAndSweeps) {
    const ExperimentSpec spec = load_spec(write(valid_spec));
    ExpandOptions opt;
    opt.gpu_available = true;
    opt.overrides = {{"cells_per_support", "3"}, {"set.layers", "1"}, {"steps", "7"}, {"merge", "no"}};
    const auto runs = expand(spec, opt);
    ASSERT_EQ(runs.size(), 2u * 2u);  // both swept keys overridden: runs x repetitions
    EXPECT_EQ(runs[0].run_id, "small-tank_rep1");
    for (const auto& r : runs) {
        EXPECT_EQ(r.solver.search.cells_per_support, 3);
        EXPECT_FALSE(r.solver.search.merge);
        EXPECT_EQ(r.scene_options.at("layers"), "1");
        EXPECT_EQ(r.steps, 7);
    }
    opt.overrides = {{"stepz", "3"}};
    try {
        expand(spec, opt);
        FAIL() << "an unknown override must be refused";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("stepz"), std::string::npos) << e.what();
    }
    opt.overrides = {{"cells_per_support", "9"}};
    EXPECT_THROW(expand(spec, opt), InputError);
}

struct BadSpec {
    const char* what;
    const char* text;
    int line;
    const char* key;
};

TEST_F(SpecTest, BadInputIsRefusedWithFileLineAndKey) {
    const std::string head = "name = \"x\"\nreproduces = \"y\"\nsteps = 10\n";  // lines 1-3
    const BadSpec cases[] = {
        {"unknown top-level key", "stepz = 4\n[[runs]]\nscene = \"tank\"\n", 4, "stepz"},
        {"unknown key in [[runs]]", "[[runs]]\nscene = \"tank\"\nstepz = 3\n", 6, "stepz"},
        {"unknown key in [sweep]", "[[runs]]\nscene = \"tank\"\n[sweep]\nmerge = [true]\nsmoothing = [1, 2]\n", 8,
         "smoothing"},
        {"wrong type", "warmup = \"two\"\n[[runs]]\nscene = \"tank\"\n", 4, "warmup"},
        {"wrong type in [solver]", "[solver]\nmerge = 1\n[[runs]]\nscene = \"tank\"\n", 5, "merge"},
        {"cells_per_support out of range", "[[runs]]\nscene = \"tank\"\nsolver = { cells_per_support = 5 }\n", 6,
         "cells_per_support"},
        {"unknown balancer", "[solver]\nbalancer = \"sometimes\"\n[[runs]]\nscene = \"tank\"\n", 5, "balancer"},
        {"devices = 0 in a sweep", "[[runs]]\nscene = \"tank\"\n[sweep]\ndevices = [1, 0]\n", 7, "devices"},
        {"repetitions = 0", "repetitions = 0\n[[runs]]\nscene = \"tank\"\n", 4, "repetitions"},
        {"unknown record item", "record = [\"summary\", \"movies\"]\n[[runs]]\nscene = \"tank\"\n", 4, "record"},
        {"snapshot_every without snapshots", "snapshot_every = 5\n[[runs]]\nscene = \"tank\"\n", 4, "snapshot_every"},
        {"unknown scene", "[[runs]]\nscene = \"teapot\"\n", 5, "teapot"},
        {"bad TOML syntax", "[[runs]]\nscene = \"tank\nlabel = \"a\"\n", 5, "TOML"},
        {"unknown key in [validation]", "[validation]\nevery = 0.1\nevry = 0.2\n[[runs]]\nscene = \"tank\"\n", 6, "evry"},
        {"[validation] without every", "[validation]\nend_time = 0.5\n[[runs]]\nscene = \"tank\"\n", 4, "every"},
        {"negative end_time", "[[runs]]\nscene = \"tank\"\nvalidation = { every = 0.1, end_time = -1 }\n", 6,
         "end_time"},
        {"validation of a scene without a metric", "[validation]\nevery = 0.1\n[[runs]]\nscene = \"dsph-dambreak\"\n",
         6, "dsph-dambreak"},
        {"unknown blow_up policy", "blow_up = \"ignore\"\n[[runs]]\nscene = \"tank\"\n", 4, "blow_up"},
        {"unknown precision", "[[runs]]\nscene = \"tank\"\nsolver = { precision = \"float16\" }\n", 6, "precision"},
    };
    for (const auto& c : cases) {
        const std::string msg = error_of(head + c.text);
        EXPECT_NE(msg.find("bad.toml:" + std::to_string(c.line) + ":"), std::string::npos) << c.what << ": " << msg;
        EXPECT_NE(msg.find(c.key), std::string::npos) << c.what << ": " << msg;
    }
    // steps = 0 on line 3, and a missing required key.
    std::string msg = error_of("name = \"x\"\nreproduces = \"y\"\nsteps = 0\n[[runs]]\nscene = \"tank\"\n");
    EXPECT_NE(msg.find("bad.toml:3:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("steps"), std::string::npos) << msg;
    msg = error_of("name = \"x\"\nsteps = 3\n[[runs]]\nscene = \"tank\"\n");
    EXPECT_NE(msg.find("bad.toml"), std::string::npos) << msg;
    EXPECT_NE(msg.find("reproduces"), std::string::npos) << msg;
    msg = error_of(head);
    EXPECT_NE(msg.find("runs"), std::string::npos) << msg;
    // The example message of the issue: the known keys are listed.
    msg = error_of(head + "[[runs]]\nscene = \"tank\"\nstepz = 3\n");
    EXPECT_NE(msg.find("unknown key 'stepz' in [[runs]] (known: scene, label, steps, end_time, set, solver, validation)"), std::string::npos) << msg;
}

TEST_F(SpecTest, MissingFileIsAnInputError) {
    EXPECT_THROW(load_spec((dir_ / "none.toml").string()), InputError);
}

TEST_F(SpecTest, SpecHashChangesWithTheContent) {
    const std::string a = spec_hash(write(valid_spec, "a.toml"));
    EXPECT_EQ(a.size(), 16u);
    EXPECT_EQ(a, spec_hash(write(valid_spec, "b.toml")));
    EXPECT_NE(a, spec_hash(write(std::string(valid_spec) + "# changed\n", "c.toml")));
    EXPECT_EQ(fnv1a_hex(""), "cbf29ce484222325");  // the FNV-1a 64 offset basis
}

TEST_F(SpecTest, ShippedSpecsAreValid) {
    for (const auto& entry : fs::directory_iterator(std::string(SPH_SOURCE_DIR) + "/experiments")) {
        if (entry.path().extension() != ".toml") continue;
        const ExperimentSpec spec = load_spec(entry.path().string());
        EXPECT_EQ(spec.name, entry.path().stem().string()) << "a spec's name is its file name";
        EXPECT_FALSE(expand(spec, ExpandOptions{}).empty()) << entry.path();
    }
}

}  // namespace
}  // namespace sph
