// The registry of implementation variants (backend/implementation_variants.hpp): each entry is
// a setting of the table (spec key, `simulate` flag, runs.csv column) with the registry's
// values and default, every value reaches SolverOptions, a bad name or value is one sentence
// and exit 2, and the variants a run used are written into its CSVs' provenance. (What each
// variant runs is checked against the host reference on a GPU: test_cuda_backend.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "backend/implementation_variants.hpp"
#include "core/error.hpp"
#include "csv_table.hpp"
#include "scratch_folder.hpp"
#include "solver_settings.hpp"
#include "sphbench_driver.hpp"

namespace fs = std::filesystem;

namespace sph {
namespace {

std::string error_of(ImplementationVariants& v, const std::string& name, const std::string& value) {
    try {
        set_implementation_variant(v, name, value);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ImplementationVariants, EachEntryHasANameValuesADefaultAndAWhy) {
    const auto& registry = implementation_variant_registry();
    ASSERT_EQ(registry.size(), 3u);
    std::set<std::string> names;
    for (const ImplementationVariant& e : registry) {
        EXPECT_TRUE(names.insert(e.name).second) << e.name << " twice";
        EXPECT_GE(e.values.size(), 2u) << e.name << ": a variant with one value is no choice";
        EXPECT_EQ(e.fallback(), "auto") << e.name << ": the default is the launch policy's own choice";
        const std::string why = e.why;
        EXPECT_GT(why.size(), 20u) << e.name;
        EXPECT_EQ(why.find('\n'), std::string::npos) << e.name << ": one line";
        for (const auto& value : e.values) {
            if (value == e.fallback()) continue;
            EXPECT_NE(why.find(value), std::string::npos) << e.name << ": the why names " << value;
        }
    }
    // The default struct holds each registry default.
    const ImplementationVariants defaults;
    for (const ImplementationVariant& e : registry) EXPECT_EQ(implementation_variant_value(defaults, e), e.fallback());
    EXPECT_EQ(describe_implementation_variants(defaults), "force_loop=auto list_build=auto list_entries=auto");
}

TEST(ImplementationVariants, EveryValueIsSetByNameAndReadBack) {
    for (const ImplementationVariant& e : implementation_variant_registry())
        for (const auto& value : e.values) {
            ImplementationVariants v;
            ASSERT_EQ(error_of(v, e.name, value), "") << e.name << "=" << value;
            EXPECT_EQ(implementation_variant_value(v, e), value);
            // Only that variant moved.
            for (const ImplementationVariant& other : implementation_variant_registry())
                if (&other != &e) {
                    EXPECT_EQ(implementation_variant_value(v, other), other.fallback());
                }
            EXPECT_EQ(v == ImplementationVariants{}, value == e.fallback()) << e.name << "=" << value;
        }
    ImplementationVariants v;
    set_implementation_variant(v, "list_build", "per-lane");
    EXPECT_EQ(v.list_build, ListBuildVariant::per_lane);
    set_implementation_variant(v, "list_entries", "plain");
    EXPECT_EQ(v.list_entries, ListEntriesVariant::plain);
    set_implementation_variant(v, "force_loop", "per-thread");
    EXPECT_EQ(v.force_loop, ForceLoopVariant::per_thread);
    EXPECT_EQ(describe_implementation_variants(v), "force_loop=per-thread list_build=per-lane list_entries=plain");
    // Several runs: per variant the values used, first seen first.
    EXPECT_EQ(describe_implementation_variants(std::vector<ImplementationVariants>{{}, v, {}}),
              "force_loop=auto|per-thread list_build=auto|per-lane list_entries=auto|plain");
}

TEST(ImplementationVariants, AnUnknownNameOrValueIsOneSentenceNamingIt) {
    ImplementationVariants v;
    const std::string value = error_of(v, "list_build", "per-warp");
    EXPECT_EQ(value, "list_build: 'per-warp' is not one of \"auto\", \"per-lane\" or \"in-step\"");
    const std::string name = error_of(v, "force_loops", "auto");
    EXPECT_EQ(name, "unknown implementation variant 'force_loops' (known: \"force_loop\", \"list_build\" or "
                    "\"list_entries\")");
    EXPECT_EQ(v, ImplementationVariants{});
}

TEST(ImplementationVariants, EachIsASettingOfTheTableWithTheRegistrysValues) {
    for (const ImplementationVariant& e : implementation_variant_registry()) {
        const SolverSetting* s = find_solver_setting(e.name);
        ASSERT_NE(s, nullptr) << e.name;
        EXPECT_EQ(s->kind, SettingKind::text);
        EXPECT_EQ(std::string(s->fallback), e.fallback());
        EXPECT_EQ(s->choices, e.values);
        EXPECT_TRUE(s->on_command_line);
        EXPECT_EQ(std::string(s->help), e.why);
    }
    EXPECT_EQ(setting_flag(*find_solver_setting("list_build")), "--list-build");
    // Every value reaches SolverOptions; the defaults give the default struct.
    EXPECT_EQ(to_solver_options(complete_solver_settings({}), false).variants, ImplementationVariants{});
    for (const ImplementationVariant& e : implementation_variant_registry())
        for (const auto& value : e.values) {
            const SolverOptions o = to_solver_options(complete_solver_settings({{e.name, value}}), false);
            EXPECT_EQ(implementation_variant_value(o.variants, e), value) << e.name;
        }
    EXPECT_THROW(check_solver_value("list_entries", "packed"), InputError);
}

class ImplementationVariantRuns : public test::ScratchFolderTest {
protected:
    ImplementationVariantRuns() : ScratchFolderTest("sph_test_variants_") {}
};

TEST_F(ImplementationVariantRuns, SimulateRefusesABadValueWithExit2) {
    std::string message;
    EXPECT_EQ(test::sphbench({"simulate", "tank", "--backend", "host", "--list-build", "per-warp", "--out",
                              dir_.string()},
                             message),
              exit_usage);
    EXPECT_NE(message.find("--list-build"), std::string::npos) << message;
    EXPECT_NE(message.find("per-warp"), std::string::npos) << message;
    EXPECT_NE(message.find("per-lane"), std::string::npos) << message << ": the allowed values are named";
}

TEST_F(ImplementationVariantRuns, SimulateWritesTheVariantsIntoItsProvenance) {
    ASSERT_EQ(test::sphbench({"simulate", "tank", "--set", "dp=0.05", "--steps", "2", "--warmup", "0", "--backend",
                              "host", "--force-loop", "per-thread", "--list-entries", "plain", "--quiet", "--out",
                              dir_.string()}),
              exit_ok);
    const CsvTable t = read_csv((dir_ / "tank_steps.csv").string());
    ASSERT_TRUE(t.meta("implementation_variants").has_value());
    EXPECT_EQ(*t.meta("implementation_variants"), "force_loop=per-thread list_build=auto list_entries=plain");
}

TEST_F(ImplementationVariantRuns, AnExperimentRecordsEachRunsVariantAndAllInItsProvenance) {
    const std::string spec = (dir_ / "variants.toml").string();
    std::ofstream(spec) << "name = \"variants\"\nreproduces = \"the variant registry's test\"\nsteps = 2\n"
                           "record = [\"summary\"]\n[solver]\nforce_loop = \"per-thread\"\n"
                           "[sweep]\nlist_build = [\"auto\", \"per-lane\"]\n"
                           "[[runs]]\nscene = \"tank\"\nlabel = \"tank\"\nset = { dp = 0.05 }\n";
    const std::string out = (dir_ / "out").string();
    ASSERT_EQ(test::sphbench({"run", spec, "--backend", "host", "--out", out, "--quiet"}), exit_ok);
    const CsvTable t = read_csv(out + "/variants/runs.csv");
    ASSERT_EQ(t.rows.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(t.cell(i, "force_loop"), "per-thread");
        EXPECT_EQ(t.cell(i, "list_entries"), "auto");
    }
    EXPECT_EQ(t.cell(0, "list_build"), "auto");
    EXPECT_EQ(t.cell(1, "list_build"), "per-lane");
    ASSERT_TRUE(t.meta("implementation_variants").has_value());
    EXPECT_EQ(*t.meta("implementation_variants"), "force_loop=per-thread list_build=auto|per-lane list_entries=auto");
    // A spec's unknown value: exit 2, naming the key.
    std::ofstream(spec) << "name = \"variants\"\nreproduces = \"x\"\nsteps = 2\n[solver]\nlist_entries = \"packed\"\n"
                           "[[runs]]\nscene = \"tank\"\n";
    std::string message;
    EXPECT_EQ(test::sphbench({"run", spec, "--backend", "host", "--out", out, "--quiet"}, message), exit_usage);
    EXPECT_NE(message.find("list_entries: 'packed'"), std::string::npos) << message;
}

}  // namespace
}  // namespace sph
