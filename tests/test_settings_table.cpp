// The solver settings table makes both the `simulate` flags and the spec keys: every entry is
// accepted by both, refused outside its range by both with the same words, and `--set` agrees.
// Then the command line's rough edges: a range as a person writes it, "abc" as not a number,
// an unknown subcommand named, an output folder that is a file refused before any work.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scratch_folder.hpp"
#include "sphbench_driver.hpp"
#include "cli_options.hpp"
#include "commands.hpp"
#include "core/error.hpp"
#include "experiment_spec.hpp"

namespace fs = std::filesystem;

namespace sph {
namespace {

// What is left of a message once the name in front of it ("--skin: ", "spec.toml:5: skin: ") is
// taken away; "" when the name is not there.
std::string after(const std::string& message, const std::string& prefix_end) {
    const auto at = message.find(prefix_end);
    return at == std::string::npos ? "" : message.substr(at + prefix_end.size());
}

class SettingsTableTest : public test::ScratchFolderTest {
protected:
    SettingsTableTest() : ScratchFolderTest("sph_test_settings_") {}

    // The flag given to a command made of the table's flags: the error message ("" when
    // accepted) and, when accepted, the value stored under the key.
    static std::string cli_error(const std::vector<std::string>& args, SettingMap& given) {
        CLI::App app{"test"};
        add_solver_options(app, given);
        std::vector<std::string> argv = {"test"};
        argv.insert(argv.end(), args.begin(), args.end());
        std::vector<char*> raw;
        for (auto& a : argv) raw.push_back(a.data());
        try {
            app.parse(int(raw.size()), raw.data());
        } catch (const CLI::ParseError& e) {
            return e.what();
        }
        return "";
    }

    // `key = toml_value` in a spec's [solver]: the error ("" when accepted) and the stored value.
    std::string spec_error(const std::string& key, const std::string& toml_value, std::string& stored) {
        const std::string path = (dir_ / "spec.toml").string();
        std::ofstream(path) << "name = \"x\"\nreproduces = \"y\"\nsteps = 1\n[solver]\n"
                            << key << " = " << toml_value << "\n[[runs]]\nscene = \"tank\"\n";
        try {
            stored = load_spec(path).solver.at(key);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }

    // `--set key=text` on a spec run.
    std::string set_error(const std::string& key, const std::string& text) {
        const std::string path = (dir_ / "ok.toml").string();
        std::ofstream(path) << "name = \"x\"\nreproduces = \"y\"\nsteps = 1\n[[runs]]\nscene = \"tank\"\n";
        ExpandOptions ex;
        ex.overrides = {{key, text}};
        try {
            expand(load_spec(path), ex);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }

};

struct Probe {
    std::string text;  // as given on the command line
    std::string toml;  // as written in a spec
};

// Values inside the range (its ends included where they belong to it) and outside it.
void probes_of(const SolverSetting& s, std::vector<Probe>& good, std::vector<Probe>& bad) {
    auto num = [](double v) {
        const std::string t = v == std::floor(v) ? std::to_string((long long)v) : format_number(v);
        return Probe{t, t};
    };
    switch (s.kind) {
    case SettingKind::integer:
    case SettingKind::number: {
        const ValueRange& r = s.range;
        ASSERT_TRUE(std::isfinite(r.lo) && std::isfinite(r.hi)) << s.key;
        good.push_back(num(r.hi));
        if (!r.lo_open) good.push_back(num(r.lo));
        if (s.kind == SettingKind::number) good.push_back(num(r.lo + (r.hi - r.lo) / 3));
        bad.push_back(num(r.lo_open ? r.lo : r.lo - 1));
        bad.push_back(num(r.hi + 1));
        if (s.kind == SettingKind::number) bad.push_back(num(r.lo - 1e-3));
        break;
    }
    case SettingKind::integer_list:
        good.push_back({format_number(s.range.lo), "[" + format_number(s.range.lo) + "]"});
        bad.push_back({format_number(s.range.hi + 1), "[" + format_number(s.range.hi + 1) + "]"});
        bad.push_back({format_number(s.range.lo - 1), "[" + format_number(s.range.lo - 1) + "]"});
        break;
    case SettingKind::text:
        for (const auto& c : s.choices) good.push_back({c, "\"" + c + "\""});
        if (std::string(s.key) == "balancer")
            for (const char* b : {"none", "simple", "every:3", "threshold"}) good.push_back({b, "\"" + std::string(b) + "\""});
        bad.push_back({"frobnicate", "\"frobnicate\""});
        break;
    case SettingKind::boolean: break;
    }
}

TEST_F(SettingsTableTest, EveryEntryIsAcceptedAndRefusedAlikeByFlagSpecAndSet) {
    int refusals_compared = 0;
    for (const SolverSetting& s : solver_settings_table()) {
        const std::string key = s.key, flag = setting_flag(s);
        std::vector<Probe> good, bad;
        probes_of(s, good, bad);
        if (s.kind == SettingKind::boolean) {
            // A switch on the command line; true and false in a spec.
            ASSERT_TRUE(s.on_command_line) << key;
            SettingMap given;
            EXPECT_EQ(cli_error({flag}, given), "") << flag;
            std::string stored;
            for (const char* v : {"true", "false"}) {
                EXPECT_EQ(spec_error(key, v, stored), "") << key;
                EXPECT_EQ(stored, v) << key;
            }
            EXPECT_EQ(given.at(key), std::string(s.fallback) == "true" ? "false" : "true") << flag;
            continue;
        }
        for (const Probe& p : good) {
            std::string stored;
            EXPECT_EQ(spec_error(key, p.toml, stored), "") << key << " = " << p.toml;
            EXPECT_EQ(set_error(key, p.text), "") << "--set " << key << "=" << p.text;
            if (!s.on_command_line) continue;
            SettingMap given;
            EXPECT_EQ(cli_error({flag, p.text}, given), "") << flag << " " << p.text;
            EXPECT_EQ(given[key], stored) << flag << " " << p.text << ": the flag and the key store the same value";
        }
        for (const Probe& p : bad) {
            std::string stored;
            const std::string from_spec = after(spec_error(key, p.toml, stored), ": " + key + ": ");
            const std::string from_set = after(set_error(key, p.text), "--set " + key + ": ");
            ASSERT_NE(from_spec, "") << key << " = " << p.toml << " is refused, naming the key";
            EXPECT_EQ(from_set, from_spec) << "--set " << key << "=" << p.text;
            EXPECT_NE(from_spec.find(p.text), std::string::npos) << from_spec << ": the value is named";
            if (!s.on_command_line) continue;
            SettingMap given;
            const std::string from_flag = after(cli_error({flag, p.text}, given), flag + ": ");
            EXPECT_EQ(from_flag, from_spec) << flag << " " << p.text;
            ++refusals_compared;
        }
    }
    EXPECT_GE(refusals_compared, 20);
}

TEST_F(SettingsTableTest, ThePreviouslyDisagreeingSettingsNowAgree) {
    // The issue's list: the GPU's name, skin's range, cfl's range, device_map in specs.
    ASSERT_NE(find_solver_setting("gpu"), nullptr);
    EXPECT_EQ(find_solver_setting("device"), nullptr);
    EXPECT_EQ(setting_flag(*find_solver_setting("gpu")), "--gpu");
    SettingMap given;
    EXPECT_NE(cli_error({"--skin", "5"}, given), "");
    std::string stored;
    EXPECT_NE(spec_error("skin", "5.0", stored), "");
    EXPECT_EQ(spec_error("device_map", "[1, 0]", stored), "");
    EXPECT_EQ(stored, "1,0");
    EXPECT_EQ(cli_error({"--device-map", "1", "0"}, given), "");
    EXPECT_EQ(given.at("device_map"), "1,0");
    EXPECT_EQ(cli_error({"--devices", "2", "--device-map", "1", "0"}, given), "");
    EXPECT_EQ(to_solver_options(complete_solver_settings(given), false).device_map, (std::vector<int>{1, 0}));
    // A map with a GPU per subdomain or none at all.
    SettingMap mismatched = {{"devices", "3"}, {"device_map", "1,0"}};
    EXPECT_THROW(to_solver_options(complete_solver_settings(mismatched), false), InputError);
}

TEST_F(SettingsTableTest, RangesReadAsAPersonWritesThem) {
    EXPECT_EQ(whole_from(1, 4).describe(), "a whole number from 1 to 4");
    EXPECT_EQ(whole_from(1).describe(), "a whole number of at least 1");
    EXPECT_EQ(number_above(0).describe(), "a number greater than 0");
    EXPECT_EQ(number_above(0, 10).describe(), "a number greater than 0 and at most 10");
    for (const SolverSetting& s : solver_settings_table()) {
        const std::string d = describe_allowed(s);
        EXPECT_LT(d.size(), 120u) << s.key << ": " << d;
        EXPECT_EQ(d.find("e+"), std::string::npos) << s.key << ": " << d;
    }
    auto message = [](const ValueRange& r, const std::string& text) {
        try {
            r.check("--steps", text);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(message(whole_from(1), "abc"), "--steps: 'abc' is not a number (allowed: a whole number of at least 1)");
    EXPECT_EQ(message(whole_from(1), "-1"), "--steps: -1 is out of range (allowed: a whole number of at least 1)");
    EXPECT_EQ(message(whole_from(1), "2.5"), "--steps: 2.5 is not a whole number (allowed: a whole number of at least 1)");
    EXPECT_EQ(message(number_above(0), "0"), "--steps: 0 is out of range (allowed: a number greater than 0)");
    EXPECT_EQ(message(number_above(0), "inf"), "--steps: 'inf' is not a number (allowed: a number greater than 0)");
    EXPECT_EQ(message(whole_from(1), "+3"), "");
    EXPECT_EQ(whole_from(1).check("n", "+3"), "3");
    EXPECT_EQ(whole_from(1).check("n", "1e6"), "1000000");
    EXPECT_EQ(number_above(0).check("n", "2.50"), "2.5");
}

using test::sphbench;

TEST_F(SettingsTableTest, TheIssuesCommandLinesGetOneSentenceEach) {
    std::string m;
    EXPECT_EQ(sphbench({"frobnicate"}, m), exit_usage);
    EXPECT_NE(m.find("unknown subcommand 'frobnicate'"), std::string::npos) << m;
    EXPECT_NE(m.find("simulate"), std::string::npos) << m;

    struct Case {
        std::vector<std::string> args;
        std::string expected;
    };
    const Case cases[] = {
        {{"--steps", "-1"}, "--steps: -1 is out of range (allowed: a whole number of at least 1)"},
        {{"--steps", "abc"}, "--steps: 'abc' is not a number (allowed: a whole number of at least 1)"},
        {{"--devices", "0"}, "--devices: 0 is out of range (allowed: a whole number from 1 to 1024)"},
        {{"--fixed-dt", "-1"}, "--fixed-dt: -1 is out of range (allowed: a number greater than 0 and at most 1000)"},
        {{"--cfl", "abc"}, "--cfl: 'abc' is not a number (allowed: a number greater than 0 and at most 1)"},
        {{"--backend", "gpu"}, "--backend: 'gpu' is not one of \"auto\", \"cuda\" or \"host\""},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args = {"simulate", "tank"};
        args.insert(args.end(), c.args.begin(), c.args.end());
        EXPECT_EQ(sphbench(args, m), exit_usage) << c.args[0];
        EXPECT_EQ(m, c.expected);
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    // `run` checks its --backend and --set values with the same words.
    EXPECT_EQ(sphbench({"run", "experiments/none.toml", "--backend", "gpu"}, m), exit_usage);
    EXPECT_EQ(m, "--backend: 'gpu' is not one of \"auto\", \"cuda\" or \"host\"");
}

// steps, warmup, snapshot_every, repetitions and end_time: one range each, read alike from a spec's top
// level, from `--set` and from `simulate`'s flag.
TEST_F(SettingsTableTest, RunSettingsAreRefusedAlikeBySpecSetAndSimulate) {
    auto top_level_error = [&](const std::string& key, const std::string& value) {
        const std::string path = (dir_ / "top.toml").string();
        std::ofstream out(path);
        out << "name = \"x\"\nreproduces = \"y\"\n";
        if (key != "steps") out << "steps = 1\n";
        out << key << " = " << value << "\n";
        if (key == "snapshot_every") out << "record = [\"snapshots\"]\n";
        out << "[[runs]]\nscene = \"tank\"\n";
        out.close();
        try {
            load_spec(path);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    int compared = 0;
    for (const RunSetting& s : run_settings_table()) {
        const std::string key = s.key, flag = setting_flag(s);
        ASSERT_TRUE(std::isfinite(s.range.lo)) << key;
        // A range open at its low end (end_time's) does not take that end itself.
        const std::string good = format_number(s.range.lo + (key == "snapshot_every" || s.range.lo_open ? 1 : 0));
        const std::string below = format_number(s.range.lo - 1);
        EXPECT_EQ(top_level_error(key, good), "") << key << " = " << good;
        if (s.settable) {
            EXPECT_EQ(set_error(key, good), "") << "--set " << key << "=" << good;
        }
        const std::string from_spec = after(top_level_error(key, below), ": " + key + ": ");
        ASSERT_NE(from_spec, "") << key << " = " << below << " is refused, naming the key";
        EXPECT_NE(from_spec.find(below), std::string::npos) << from_spec;
        EXPECT_NE(from_spec.find(s.range.describe()), std::string::npos) << from_spec;
        if (s.settable) {
            EXPECT_EQ(after(set_error(key, below), "--set " + key + ": "), from_spec) << key;
        }
        if (s.simulate_default) {
            std::string m;
            EXPECT_EQ(sphbench({"simulate", "tank", flag, below}, m), exit_usage) << flag;
            EXPECT_EQ(after(m, flag + ": "), from_spec) << flag;
            ++compared;
        }
    }
    EXPECT_EQ(compared, 4);  // steps, warmup, snapshot_every, end_time
    // steps has no default in a spec; `simulate` warms up by default.
    EXPECT_EQ(run_setting("steps").fallback, nullptr);
    EXPECT_STREQ(run_setting("warmup").simulate_default, "10");
}

TEST_F(SettingsTableTest, AnOutputFolderThatIsAFileIsRefusedBeforeAnyRun) {
    const std::string file = (dir_ / "taken").string();
    std::ofstream(file) << "not a folder\n";
    std::string m;
    // Enough steps that a run would take a while: the refusal must come first, as bad input.
    EXPECT_EQ(sphbench({"simulate", "tank", "--steps", "100000", "--quiet", "--backend", "host", "--out", file}, m),
              exit_usage);
    EXPECT_NE(m.find("--out"), std::string::npos) << m;
    EXPECT_NE(m.find(file), std::string::npos) << m;
    EXPECT_EQ(sphbench({"simulate", "tank", "--steps", "100000", "--quiet", "--backend", "host", "--out",
                        file + "/below"},
                       m),
              exit_usage);
    EXPECT_NE(m.find("is a file"), std::string::npos) << m;

    const std::string spec = (dir_ / "one.toml").string();
    std::ofstream(spec) << "name = \"one\"\nreproduces = \"y\"\nsteps = 100000\n[[runs]]\nscene = \"tank\"\n";
    EXPECT_EQ(sphbench({"run", spec, "--backend", "host", "--quiet", "--out", file}, m), exit_usage);
    EXPECT_NE(m.find("--out"), std::string::npos) << m;
    // A folder that does not exist yet is fine: it is made when results are written.
    EXPECT_NO_THROW(check_output_folder("--out", (dir_ / "new" / "deeper").string()));
}

// Issue 13's MPI switches: --share-gpus and --gpu-direct, spec keys share_gpus and gpu_direct,
// off by default; a value that is not a boolean is refused by name; GPU-direct on the host
// backend or in one process is one sentence and bad input.
TEST_F(SettingsTableTest, TheMpiGpuSwitchesAreKeysOfTheTable) {
    for (const char* key : {"share_gpus", "gpu_direct"}) {
        const SolverSetting* s = find_solver_setting(key);
        ASSERT_NE(s, nullptr) << key;
        EXPECT_EQ(s->kind, SettingKind::boolean) << key;
        EXPECT_STREQ(s->fallback, "false") << key;
    }
    EXPECT_EQ(setting_flag(*find_solver_setting("share_gpus")), "--share-gpus");
    EXPECT_EQ(setting_flag(*find_solver_setting("gpu_direct")), "--gpu-direct");
    SettingMap given;
    EXPECT_EQ(cli_error({"--share-gpus", "--gpu-direct"}, given), "");
    const SolverOptions o = to_solver_options(complete_solver_settings(given), false);
    EXPECT_TRUE(o.share_gpus);
    EXPECT_TRUE(o.gpu_direct);
    const SolverOptions d = to_solver_options(complete_solver_settings({}), false);
    EXPECT_FALSE(d.share_gpus);
    EXPECT_FALSE(d.gpu_direct);
    std::string stored;
    EXPECT_EQ(spec_error("share_gpus", "true", stored), "");
    EXPECT_EQ(stored, "true");
    EXPECT_NE(spec_error("gpu_direct", "\"maybe\"", stored), "");
    EXPECT_EQ(set_error("share_gpus", "maybe"), "--set share_gpus: 'maybe' is not true or false");
    std::string m;
    EXPECT_EQ(sphbench({"simulate", "tank", "--backend", "host", "--devices", "2", "--gpu-direct", "--quiet"}, m),
              exit_usage);
    EXPECT_NE(m.find("this run uses the host backend"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

}  // namespace
}  // namespace sph
