// Gauges (solver/gauge.hpp, physics/gauges.hpp) against exact answers and simple references:
// a tank at rest (level, pressure, velocity, the water's weight on the tank), a free-falling
// block (no force), the brute-force sums over a snapshot, two subdomains against one, and
// gauges that do not fit the scene.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "case_file.hpp"
#include "commands.hpp"
#include "experiment_spec.hpp"
#include "gauge_options.hpp"
#include "sphbench_driver.hpp"
#include "test_support.hpp"
#include "core/smoothing_kernels.hpp"
#include "simulation.hpp"

namespace sph {
namespace {

using test::gauge_at;

Scene small_tank() {
    return make_scene("tank", {{"length", "0.2"}, {"width", "0.1"}, {"depth", "0.3"}, {"dp", "0.0125"}});
}

// The brute-force Shepard interpolation of the snapshot's fluid at x: pressure and the weight sum.
struct Reference {
    double pressure = 0, weight = 0, mass_sum = 0, top = -1e300;
};
Reference reference_at(const Scene& s, const SnapshotData& snap, const double x[3], double radius) {
    Reference r;
    const double h = s.params.h, support = s.params.support;
    double num = 0;
    for (std::size_t i = 0; i < snap.id.size(); ++i) {
        if (snap.type[i] != 0) continue;
        const double d[3] = {x[0] - snap.position[3 * i], x[1] - snap.position[3 * i + 1], x[2] - snap.position[3 * i + 2]};
        if (d[0] * d[0] + d[1] * d[1] <= radius * radius) r.top = std::max(r.top, snap.position[3 * i + 2]);
        const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (dist >= support) continue;
        const double w = s.kernel == KernelType::wendland ? double(WendlandC2(real(h)).w(real(dist)))
                                                          : double(CubicSpline(real(h)).w(real(dist)));
        const double v = double(s.params.mass) / snap.density[i];
        num += snap.pressure[i] * v * w;
        r.weight += v * w;
        r.mass_sum += double(s.params.mass) * w;
    }
    r.pressure = num / r.weight;
    return r;
}

double fluid_top(const SnapshotData& snap) {
    double top = -1e300;
    for (std::size_t i = 0; i < snap.id.size(); ++i)
        if (snap.type[i] == 0) top = std::max(top, snap.position[3 * i + 2]);
    return top;
}

TEST(Gauges, TankAtRestReadsItsLevelPressureAndWeight) {
    const Scene s = small_tank();
    Simulation sim(s, SolverOptions{});
    for (int k = 0; k < 100; ++k) sim.step();
    const SnapshotData snap = sim.snapshot();
    const double surface = fluid_top(snap) + 0.5 * s.dp;  // as the scene starts it: half a spacing above the top layer
    const double x = 0.1, y = 0.05, z = surface - 0.2;   // 16 spacings deep, 8 from the side walls
    Gauge force = gauge_at(GaugeKind::force, "tank_force", 0, 0);
    force.body = "tank";
    Gauge top = gauge_at(GaugeKind::max_height, "top", x, y);
    top.radius = 2 * s.dp;
    const std::vector<Gauge> gauges = {gauge_at(GaugeKind::water_level, "level", x, y),
                                       gauge_at(GaugeKind::pressure, "p", x, y, z),
                                       gauge_at(GaugeKind::velocity, "v", x, y, z), force, top};
    sim.check_gauges(gauges);
    const std::vector<double> v = sim.measure_gauges(gauges);
    ASSERT_EQ(v.size(), 1u + 1 + 3 + 3 + 1);
    const double level = v[0], pressure = v[1], fz = v[7];
    EXPECT_NEAR(level, surface, s.dp) << "water level";
    const double rho_g = s.params.rho0 * 9.81;
    EXPECT_NEAR(pressure, rho_g * (surface - z), 0.02 * rho_g * (surface - z)) << "pressure 0.2 m deep";
    for (int k = 2; k < 5; ++k) EXPECT_LT(std::abs(v[k]), 0.02) << "velocity component " << k - 2;
    const double weight = double(s.fluid_count()) * s.params.mass * 9.81;
    EXPECT_NEAR(fz, -weight, 0.01 * weight) << "the water's weight on the tank";
    EXPECT_LT(std::abs(v[5]), 0.01 * weight);
    EXPECT_LT(std::abs(v[6]), 0.01 * weight);

    // The same sums by brute force over the snapshot's particles.
    const double at[3] = {x, y, z};
    const Reference ref = reference_at(s, snap, at, top.radius);
    EXPECT_NEAR(pressure, ref.pressure, 1e-4 * std::abs(ref.pressure));
    EXPECT_NEAR(v[8], ref.top, 1e-5);
    std::printf("tank at rest: level %.5f m (surface %.5f), pressure %.2f Pa (rho g depth %.2f), Fz %.3f N "
                "(weight %.3f N), Fx %.3g, Fy %.3g\n",
                level, surface, pressure, rho_g * (surface - z), fz, weight, v[5], v[6]);
}

// With Verlet lists the particles stray from the cells of the last sort until the next
// rebuild: a collapsing column read between rebuilds against brute-force sums of its snapshot.
TEST(Gauges, VerletListsBetweenRebuildsReadWhatTheParticlesSay) {
    const Scene s = make_scene("dambreak", {{"dp", "0.025"}, {"length", "0.6"}, {"height", "0.5"},
                                            {"column_width", "0.3"}, {"column_height", "0.4"}});
    SolverOptions o;
    o.search.verlet = true;
    o.search.rebuild_every = 60;  // the lists stay 60 steps (the skin is not reached at these speeds)
    Simulation sim(s, o);
    for (int k = 0; k < 150; ++k) sim.step();  // 30 steps after a rebuild, the column moving
    const SnapshotData snap = sim.snapshot();
    Gauge top = gauge_at(GaugeKind::max_height, "top", 0.3, 0.1);
    top.radius = 0.05;
    const std::vector<Gauge> gauges = {gauge_at(GaugeKind::pressure, "p", 0.3, 0.1, 0.04), top};
    const std::vector<double> v = sim.measure_gauges(gauges);
    const double at[3] = {0.3, 0.1, 0.04};
    const Reference ref = reference_at(s, snap, at, top.radius);
    EXPECT_GT(ref.weight, 0.5);
    EXPECT_NEAR(v[0], ref.pressure, 1e-4 * std::abs(ref.pressure) + 1e-3);
    EXPECT_NEAR(v[1], ref.top, 1e-5);
    EXPECT_GT(sim.neighbour_list_builds(), 1);
}

TEST(Gauges, WaterLevelIsWhereTheKernelSummedMassFallsToHalfAParticle) {
    const Scene s = small_tank();
    Simulation sim(s, SolverOptions{});
    for (int k = 0; k < 20; ++k) sim.step();
    const SnapshotData snap = sim.snapshot();
    const double x = 0.07, y = 0.04;
    const double level = sim.measure_gauges({gauge_at(GaugeKind::water_level, "level", x, y)})[0];
    const double threshold = 0.5 * s.params.mass / (s.dp * s.dp * s.dp);
    // Just below the level the mass sum is at least the threshold, just above it is less.
    const double below[3] = {x, y, level - 0.01 * s.dp}, above[3] = {x, y, level + 0.01 * s.dp};
    EXPECT_GT(reference_at(s, snap, below, 0).mass_sum, threshold);
    EXPECT_LT(reference_at(s, snap, above, 0).mass_sum, threshold);
}

// Read from the bottom up as DualSPHysics reads it: a block of water above the free surface (spray,
// a jet off an obstacle) on the same line does not lift the level; read from the top down it did.
TEST(Gauges, WaterLevelIsTheWaterBodysSurfaceNotSprayAboveIt) {
    namespace fs = std::filesystem;
    const fs::path file = fs::temp_directory_path() / "sph_gauges_spray.toml";
    std::ofstream(file) << "[case]\ndp = 0.02\n[case.tank]\nmin = [0, 0, 0]\nmax = [0.3, 0.3, 0.6]\n"
                           "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.3, 0.3, 0.1]\n"
                           "[[case.fluid]]\nmin = [0.1, 0.1, 0.3]\nmax = [0.2, 0.2, 0.4]\nhydrostatic = false\n";
    const Scene s = build_scene(case_scene_prefix + file.string(), {});
    fs::remove(file);
    Simulation sim(s, SolverOptions{});
    sim.step();
    const std::vector<double> v = sim.measure_gauges({gauge_at(GaugeKind::water_level, "under_spray", 0.15, 0.15),
                                                      gauge_at(GaugeKind::water_level, "beside", 0.05, 0.05)});
    EXPECT_NEAR(v[0], 0.1, s.dp) << "the level under the block";
    EXPECT_NEAR(v[0], v[1], 0.1 * s.dp) << "the same water body, with and without a block above";
}

TEST(Gauges, AFreeFallingBlockFeelsNoForceAndNoPressure) {
    namespace fs = std::filesystem;
    const fs::path file = fs::temp_directory_path() / "sph_gauges_free_fall.toml";
    std::ofstream(file) << "[case]\ndp = 0.025\n[case.tank]\nmin = [0, 0, 0]\nmax = [0.4, 0.4, 0.6]\n"
                           "[[case.fluid]]\nmin = [0.1, 0.1, 0.3]\nmax = [0.3, 0.3, 0.5]\nhydrostatic = false\n";
    const Scene s = build_scene(case_scene_prefix + file.string(), {});
    fs::remove(file);
    Simulation sim(s, SolverOptions{});
    while (sim.time() < 0.05) sim.step();  // 1 cm of fall: still clear of the floor
    Gauge force = gauge_at(GaugeKind::force, "tank", 0, 0);
    force.body = "tank";
    const double z_centre = 0.4 - 0.5 * 9.81 * sim.time() * sim.time();
    const std::vector<double> v = sim.measure_gauges(
        {force, gauge_at(GaugeKind::pressure, "p", 0.3, 0.3, z_centre), gauge_at(GaugeKind::velocity, "v", 0.3, 0.3, z_centre)});
    EXPECT_EQ(v[0], 0.0);
    EXPECT_EQ(v[1], 0.0);
    EXPECT_EQ(v[2], 0.0);
    EXPECT_LT(std::abs(v[3]), 0.02 * s.params.rho0 * 9.81 * 0.1) << "pressure inside a falling block";
    EXPECT_NEAR(v[6], -9.81 * sim.time(), 0.01 * 9.81 * sim.time()) << "the block falls freely";
}

TEST(Gauges, TwoSubdomainsReadWhatOneReads) {
    const Scene s = small_tank();
    Gauge force = gauge_at(GaugeKind::force, "tank", 0, 0);
    force.body = "tank";
    Gauge top = gauge_at(GaugeKind::max_height, "top", 0.1, 0.05);
    top.radius = 0.03;
    // Points on both sides of the slab boundary (x = 0.1 splits the fluid in two).
    const std::vector<Gauge> gauges = {gauge_at(GaugeKind::water_level, "level", 0.1, 0.05),
                                       gauge_at(GaugeKind::pressure, "p", 0.095, 0.05, 0.1),
                                       gauge_at(GaugeKind::velocity, "v", 0.105, 0.05, 0.2), force, top};
    std::vector<std::vector<double>> runs;
    for (int devices : {1, 2}) {
        SolverOptions o;
        o.subdomains = devices;
        Simulation sim(s, o);
        for (int k = 0; k < 50; ++k) sim.step();
        ASSERT_EQ(sim.subdomain_count(), devices);
        runs.push_back(sim.measure_gauges(gauges));
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    const char* what[] = {"level", "p", "vx", "vy", "vz", "fx", "fy", "fz", "top"};
    const double weight = double(s.fluid_count()) * s.params.mass * 9.81;
    const double scale[] = {1, 1e3, 1e-3, 1e-3, 1e-3, weight, weight, weight, 1};
    for (std::size_t k = 0; k < runs[0].size(); ++k) {
        EXPECT_NEAR(runs[1][k], runs[0][k], 1e-5 * scale[k]) << what[k];
        std::printf("%s: 1 subdomain %.9g, 2 subdomains %.9g\n", what[k], runs[0][k], runs[1][k]);
    }
}

TEST(Gauges, GaugesThatDoNotFitTheSceneAreRefusedNamingThem) {
    const Scene s = small_tank();
    Simulation sim(s, SolverOptions{});
    auto refusal = [&](const Gauge& g) {
        try {
            sim.check_gauges({g});
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(refusal(gauge_at(GaugeKind::pressure, "p", 0.1, 0.05, 9)).find("gauge 'p' (pressure): z = 9 lies outside"),
              std::string::npos);
    Gauge body = gauge_at(GaugeKind::force, "f", 0, 0);
    body.body = "lid";
    EXPECT_NE(refusal(body).find("has no body 'lid'; its bodies are 'tank'"), std::string::npos) << refusal(body);
    Gauge top = gauge_at(GaugeKind::max_height, "top", 0.1, 0.05);
    EXPECT_NE(refusal(top).find("radius must be above 0"), std::string::npos);
    EXPECT_EQ(refusal(gauge_at(GaugeKind::water_level, "level", 0.1, 0.05, 99)), "");  // z is not read
    EXPECT_THROW(gauge_kind("swl"), InputError);
    EXPECT_EQ(gauge_kind("water_level"), GaugeKind::water_level);
}

}  // namespace
}  // namespace sph

namespace sph {
namespace {

std::vector<std::string> csv_lines(const std::filesystem::path& path) {
    std::vector<std::string> lines;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);)
        if (!line.empty() && line[0] != '#') lines.push_back(line);
    return lines;
}

TEST(GaugesCli, SimulateWritesGaugesEveryIntervalOfSimulatedTime) {
    namespace fs = std::filesystem;
    const fs::path out = fs::temp_directory_path() / "sph_gauges_cli";
    fs::remove_all(out);
    std::string message;
    ASSERT_EQ(test::sphbench({"simulate", "tank", "--set", "dp=0.04", "--backend", "host", "--steps", "60", "--warmup",
                              "0", "--quiet", "--out", out.string(), "--gauge", "water_level:x=0.2,y=0.1,every=0.002",
                              "--gauge", "force:body=tank,every=0.004,name=tank"},
                             message),
              exit_ok)
        << message;
    const std::vector<std::string> lines = csv_lines(out / "tank_gauges.csv");
    ASSERT_GE(lines.size(), 3u);
    EXPECT_EQ(lines[0], "time,water_level1,tank_x,tank_y,tank_z");
    // Rows at t = 0 and then whenever a gauge came due; the force every other row.
    double previous = -1;
    int with_force = 0;
    for (std::size_t k = 1; k < lines.size(); ++k) {
        const double t = std::stod(lines[k]);
        if (k > 1) {
            EXPECT_NEAR(t - previous, 0.002, 0.001) << lines[k];
        }
        previous = t;
        with_force += lines[k].find(",,") == std::string::npos;
    }
    EXPECT_EQ(with_force, int(lines.size() - 1 + 1) / 2);
    std::ifstream raw(out / "tank_gauges.csv");
    std::string text((std::istreambuf_iterator<char>(raw)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("# gauge.tank: force body=tank every=0.004"), std::string::npos);
    EXPECT_NE(text.find("# git_commit: "), std::string::npos);
    fs::remove_all(out);
}

// `sphbench simulate` for 20 steps on the host of a small case with three gauges of its own (a
// level, an unnamed pressure and the force on the tank), with `gauges` as --gauge options: the
// path of its _gauges.csv.
std::filesystem::path simulate_gauged_case(const std::filesystem::path& folder, const std::vector<std::string>& gauges) {
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    const std::filesystem::path file = folder / "gauged.toml";
    std::ofstream(file) << "[case]\ndp = 0.04\n[case.tank]\nmin = [0, 0, 0]\nmax = [0.4, 0.2, 0.4]\n"
                           "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.2, 0.2, 0.2]\n"
                           "[[case.gauges]]\nkind = \"water_level\"\nname = \"level\"\nx = 0.1\ny = 0.1\nevery = 0.004\n"
                           "[[case.gauges]]\nkind = \"pressure\"\nx = 0.1\ny = 0.1\nz = 0.06\nevery = 0.004\n"
                           "[[case.gauges]]\nkind = \"force\"\nname = \"walls\"\nbody = \"tank\"\nevery = 0.004\n";
    std::vector<std::string> args = {"simulate", "case:" + file.string(), "--backend", "host", "--steps", "20",
                                     "--warmup", "0", "--quiet", "--out", (folder / "out").string()};
    for (const std::string& g : gauges) args.insert(args.end(), {"--gauge", g});
    std::string message;
    EXPECT_EQ(test::sphbench(args, message), exit_ok) << message;
    return folder / "out" / "gauged_gauges.csv";
}

std::string text_of(const std::filesystem::path& path) {
    std::ifstream raw(path);
    return std::string((std::istreambuf_iterator<char>(raw)), std::istreambuf_iterator<char>());
}

TEST(GaugesCli, SimulateSamplesACaseFilesGaugesWithNoneGiven) {
    namespace fs = std::filesystem;
    const fs::path folder = fs::temp_directory_path() / "sph_gauges_case";
    const fs::path csv = simulate_gauged_case(folder, {});
    const std::vector<std::string> lines = csv_lines(csv);
    ASSERT_GE(lines.size(), 3u);
    EXPECT_EQ(lines[0], "time,level,pressure1,walls_x,walls_y,walls_z");
    const std::string text = text_of(csv);
    EXPECT_NE(text.find("# gauge.level: water_level x=0.1 y=0.1 every=0.004"), std::string::npos) << text;
    // The case's level at x = 0.1 stands in its water, 0.2 m deep at the start.
    const std::string first = lines[1].substr(lines[1].find(',') + 1);
    EXPECT_NEAR(std::stod(first), 0.2, 0.04) << lines[1];
    fs::remove_all(folder);
}

TEST(GaugesCli, AGaugeNamedAsACaseGaugeReplacesItAndOthersAreAppended) {
    namespace fs = std::filesystem;
    const fs::path folder = fs::temp_directory_path() / "sph_gauges_case_override";
    const fs::path csv = simulate_gauged_case(folder, {"water_level:name=level,x=0.3,y=0.1,every=0.002",
                                                       "pressure:x=0.1,y=0.1,z=0.1,every=0.002",
                                                       "velocity:name=v,x=0.1,y=0.1,z=0.1,every=0.004"});
    const std::vector<std::string> lines = csv_lines(csv);
    ASSERT_GE(lines.size(), 4u);
    EXPECT_EQ(lines[0], "time,level,pressure1,walls_x,walls_y,walls_z,pressure2,v_x,v_y,v_z");
    const std::string text = text_of(csv);
    EXPECT_NE(text.find("# gauge.level: water_level x=0.3 y=0.1 every=0.002"), std::string::npos) << text;
    EXPECT_NE(text.find("# gauge.pressure1: pressure x=0.1 y=0.1 z=0.06 every=0.004"), std::string::npos) << text;
    EXPECT_NE(text.find("# gauge.pressure2: pressure x=0.1 y=0.1 z=0.1 every=0.002"), std::string::npos) << text;
    // The level now every 2 ms: a value in every row, the case's 4 ms gauges in every other.
    int with_level = 0, with_case_pressure = 0;
    for (std::size_t k = 1; k < lines.size(); ++k) {
        std::vector<std::string> cells;
        std::stringstream row(lines[k]);
        for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
        cells.resize(10);
        with_level += !cells[1].empty();
        with_case_pressure += !cells[2].empty();
    }
    EXPECT_EQ(with_level, int(lines.size()) - 1);
    EXPECT_LT(with_case_pressure, with_level);
    // The level moved to x = 0.3, a dry line at the start (the water stands at x < 0.2).
    EXPECT_EQ(lines[1].substr(0, lines[1].find(',', lines[1].find(',') + 1)), "0,nan");
    fs::remove_all(folder);
}

TEST(GaugesCli, BadGaugesExit2BeforeAnyStep) {
    namespace fs = std::filesystem;
    const fs::path out = fs::temp_directory_path() / "sph_gauges_bad";
    fs::remove_all(out);
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"swl:x=0.2,y=0.1,every=0.01", "unknown gauge kind 'swl'"},
        {"water_level:x=0.2,y=0.1,z=0.3,every=0.01", "unknown key 'z' for a water_level gauge"},
        {"pressure:x=0.2,y=0.1,every=0.01", "a pressure gauge needs 'z'"},
        {"pressure:x=0.2,y=0.1,z=7,every=0.01", "gauge 'pressure1' (pressure): z = 7 lies outside the domain"},
        {"force:body=lid,every=0.01", "scene 'tank' has no body 'lid'"},
        {"water_level:x=0.2,y=0.1", "needs 'every'"},
        {"max_height:x=0.2,y=0.1,radius=0,every=0.1", "'radius' must be above 0"}};
    for (const auto& [gauge_text, expected] : bad) {
        std::string message;
        EXPECT_EQ(test::sphbench({"simulate", "tank", "--set", "dp=0.04", "--backend", "host", "--steps", "5", "--quiet",
                                  "--out", out.string(), "--gauge", gauge_text},
                                 message),
                  exit_usage)
            << gauge_text;
        EXPECT_NE(message.find(expected), std::string::npos) << message;
        EXPECT_FALSE(fs::exists(out / "tank_steps.csv")) << "a step was taken for " << gauge_text;
    }
    fs::remove_all(out);
}

TEST(GaugesSpec, GaugeTablesAreReadStrictly) {
    namespace fs = std::filesystem;
    const fs::path file = fs::temp_directory_path() / "sph_gauges_spec.toml";
    const std::string head = "name = \"g\"\nreproduces = \"gauges\"\nsteps = 5\n[[runs]]\nscene = \"tank\"\n";
    std::ofstream(file) << head
                        << "[[gauges]]\nkind = \"water_level\"\nname = \"wg1\"\nx = 0.2\ny = 0.1\nevery = 0.01\n"
                           "[[gauges]]\nkind = \"force\"\nbody = \"tank\"\nevery = 1\n";
    const ExperimentSpec spec = load_spec(file.string());
    ASSERT_EQ(spec.gauges.size(), 2u);
    EXPECT_EQ(spec.gauges[0].name, "wg1");
    EXPECT_EQ(spec.gauges[0].kind, GaugeKind::water_level);
    EXPECT_EQ(spec.gauges[0].x, 0.2);
    EXPECT_EQ(spec.gauges[1].name, "") << "named in the run, after a case file's gauges (merge_gauges)";
    EXPECT_EQ(spec.gauges[1].every, 1.0);
    std::ofstream(file) << head << "[[gauges]]\nkind = \"velocity\"\nx = 0.2\ny = 0.1\nz = 0.1\nradius = 2\nevery = 0.01\n";
    try {
        load_spec(file.string());
        ADD_FAILURE() << "a velocity gauge with a radius was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(":6: [[gauges]] 1: unknown key 'radius' for a velocity gauge"),
                  std::string::npos)
            << e.what();
    }
    // A name given twice, or one an unnamed gauge would be given: refused at load, naming both lines.
    const std::string level = "[[gauges]]\nkind = \"water_level\"\nname = \"wg1\"\nx = 0.2\ny = 0.1\nevery = 0.01\n";
    std::ofstream(file) << head << level << level;
    try {
        load_spec(file.string());
        ADD_FAILURE() << "two gauges named wg1 were accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(":14: gauge name 'wg1' is used twice (also at " + file.string() + ":8)"),
                  std::string::npos)
            << e.what();
    }
    std::ofstream(file) << head << "[[gauges]]\nkind = \"force\"\nbody = \"tank\"\nevery = 1\n"
                        << "[[gauges]]\nkind = \"force\"\nname = \"force1\"\nbody = \"tank\"\nevery = 1\n";
    EXPECT_THROW(load_spec(file.string()), InputError);
    fs::remove(file);
}

Gauge named(GaugeKind kind, const std::string& name, double every) {
    Gauge g = gauge_at(kind, name, 0.1, 0.1, 0.1);
    g.every = every;
    return g;
}

// The rule of run_scene: the case's gauges in their order, a request's gauge of a case gauge's
// name in its place, the request's others after; unnamed ones named last, over the whole list.
TEST(GaugesMerge, RequestGaugesReplaceCaseGaugesOfTheirNameAndTheOthersFollow) {
    const std::vector<Gauge> from_case = {named(GaugeKind::water_level, "H1", 0.005),
                                          named(GaugeKind::pressure, "P1", 0.001),
                                          named(GaugeKind::pressure, "pressure1", 0.001)};  // named by the case
    const std::vector<Gauge> requested = {named(GaugeKind::velocity, "V", 0.01), named(GaugeKind::pressure, "P1", 1e-5),
                                          named(GaugeKind::pressure, "", 0.002)};
    const std::vector<Gauge> gauges = merge_gauges(from_case, requested);
    std::vector<std::string> names;
    for (const Gauge& g : gauges) names.push_back(g.name);
    EXPECT_EQ(names, (std::vector<std::string>{"H1", "P1", "pressure1", "V", "pressure3"}));
    EXPECT_EQ(gauges[1].every, 1e-5) << "the request's P1 in the case's place";
    EXPECT_EQ(gauges[4].every, 0.002) << "an unnamed request gauge is appended, not put in the case's pressure1";
    // Without a case: the request's gauges as they were sampled before case gauges existed.
    const std::vector<Gauge> alone = merge_gauges({}, requested);
    EXPECT_EQ(alone.size(), 3u);
    EXPECT_EQ(alone[2].name, "pressure2");
    EXPECT_TRUE(merge_gauges(from_case, {}).size() == 3u);
    // A name the request gives twice would replace one case gauge twice: refused.
    EXPECT_THROW(merge_gauges(from_case, {named(GaugeKind::pressure, "P1", 0.1), named(GaugeKind::pressure, "P1", 0.2)}),
                 InputError);
}

}  // namespace
}  // namespace sph
