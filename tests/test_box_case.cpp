// Cases without C++ (harness/case_file.hpp, solver/scenes/box_case.hpp): the case files of the
// tank and dam-break scenes make the particles the C++ scenes make, SPHERIC Test 2 builds with
// its volumes and its box, and bad case files are refused naming the file, the line and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "case_file.hpp"
#include "core/error.hpp"
#include "experiment_spec.hpp"
#include "scratch_folder.hpp"
#include "sphbench_driver.hpp"

namespace sph {
namespace {

std::string case_path(const std::string& name) { return std::string(SPH_SOURCE_DIR) + "/experiments/cases/" + name + ".toml"; }
std::string case_scene(const std::string& name) { return case_scene_prefix + case_path(name); }

// Same particles in the same order: positions, boundary or fluid, velocities, densities.
void expect_same_particles(const Scene& expected, const Scene& got, const std::string& what) {
    ASSERT_EQ(got.size(), expected.size()) << what;
    ASSERT_EQ(got.n_boundary, expected.n_boundary) << what;
    ASSERT_EQ(got.density.size(), expected.density.size()) << what;
    for (std::size_t i = 0; i < got.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_NEAR(got.position[i][k], expected.position[i][k], 1e-12) << what << " particle " << i;
            ASSERT_EQ(got.velocity[i][k], expected.velocity[i][k]) << what << " particle " << i;
        }
        if (!got.density.empty()) {
            ASSERT_EQ(got.density[i], expected.density[i]) << what << " particle " << i;
        }
    }
    EXPECT_EQ(got.kernel, expected.kernel) << what;
    EXPECT_FLOAT_EQ(got.params.h, expected.params.h) << what;
    EXPECT_FLOAT_EQ(got.params.c0, expected.params.c0) << what;
    EXPECT_FLOAT_EQ(got.params.mass, expected.params.mass) << what;
    EXPECT_EQ(got.cfl, expected.cfl) << what;
    ASSERT_EQ(got.bodies.size(), expected.bodies.size()) << what;
    for (std::size_t b = 0; b < got.bodies.size(); ++b) {
        EXPECT_EQ(got.bodies[b].name, expected.bodies[b].name) << what;
        EXPECT_EQ(got.bodies[b].first, expected.bodies[b].first) << what;
        EXPECT_EQ(got.bodies[b].count, expected.bodies[b].count) << what;
    }
}

void expect_same_domain(const Scene& expected, const Scene& got, const std::string& what) {
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(got.lo[k], expected.lo[k], 1e-9) << what << " axis " << k;
        EXPECT_NEAR(got.hi[k], expected.hi[k], 1e-9) << what << " axis " << k;
    }
}

TEST(BoxCase, TankCaseMakesTheTankScenesParticles) {
    const Scene scene = make_scene("tank", {{"dp", "0.02"}});
    const Scene built = build_scene(case_scene("tank"), {});
    ASSERT_FALSE(scene.density.empty());  // the hydrostatic start is compared too
    expect_same_particles(scene, built, "tank");
    expect_same_domain(scene, built, "tank");
    ASSERT_EQ(built.bodies.size(), 1u);
    EXPECT_EQ(built.bodies[0].name, "tank");
    EXPECT_EQ(built.bodies[0].count, built.n_boundary);
}

TEST(BoxCase, DamBreakCaseMakesTheDamBreakScenesParticles) {
    for (const char* dp : {"0.02", "0.033"}) {
        const Scene scene = make_scene("dambreak", {{"dp", dp}});
        const Scene built = build_scene(case_scene("dambreak"), {{"dp", dp}});
        EXPECT_TRUE(built.density.empty());  // started at rho0, as the C++ scene
        expect_same_particles(scene, built, std::string("dambreak dp ") + dp);
        expect_same_domain(scene, built, std::string("dambreak dp ") + dp);
    }
}

TEST(BoxCase, DualSphysicsDamBreakCaseMakesItsParticles) {
    for (const char* dp : {"0.02", "0.0137"}) {
        const Scene scene = make_scene("dsph-dambreak", {{"dp", dp}});
        const Scene built = build_scene(case_scene("dsph-dambreak"), {{"dp", dp}});
        expect_same_particles(scene, built, std::string("dsph-dambreak dp ") + dp);
        expect_same_domain(scene, built, std::string("dsph-dambreak dp ") + dp);
        const BoundaryBody* obstacle = built.body("obstacle");
        ASSERT_NE(obstacle, nullptr);
        EXPECT_GT(obstacle->count, 100u);
    }
}

TEST(BoxCase, SphericTest2BuildsWithItsVolumesAndItsBox) {
    const double dp = 0.02;
    const Scene s = build_scene(case_scene("spheric-test2"), {{"dp", "0.02"}});
    const double water = 1.228 * 1.0 * 0.55 / (dp * dp * dp);
    EXPECT_NEAR(double(s.fluid_count()), water, 0.03 * water);
    // One layer of walls: floor, two sides and two ends of the open tank.
    const BoundaryBody* tank = s.body("tank");
    ASSERT_NE(tank, nullptr);
    const double walls = (3.22 * 1.0 + 2 * 3.22 * 1.0 + 2 * 1.0 * 1.0) / (dp * dp);
    EXPECT_NEAR(double(tank->count), walls, 0.05 * walls);
    // The box: its top and four sides (its bottom is the floor), inside its bounds.
    const BoundaryBody* box = s.body("box");
    ASSERT_NE(box, nullptr);
    EXPECT_EQ(box->first, tank->count);
    EXPECT_EQ(box->first + box->count, s.n_boundary);
    const double faces = (0.161 * 0.403 + 2 * 0.161 * 0.161 + 2 * 0.403 * 0.161) / (dp * dp);
    EXPECT_NEAR(double(box->count), faces, 0.25 * faces);
    const double lo[3] = {0.6635, 0.295, 0}, hi[3] = {0.8245, 0.698, 0.161};
    for (std::size_t i = box->first; i < box->first + box->count; ++i)
        for (int k = 0; k < 3; ++k) {
            ASSERT_GE(s.position[i][k], lo[k] - dp / 2) << i;
            ASSERT_LE(s.position[i][k], hi[k] + dp / 2) << i;
        }
    // The water against the far wall, hydrostatic: denser at the bottom than at the top.
    float bottom = 0, top = 1e9f;
    for (std::size_t i = s.n_boundary; i < s.size(); ++i) {
        ASSERT_GE(s.position[i][0], 1.992 - dp / 2) << i;
        ASSERT_LE(s.position[i][2], 0.55 + dp) << i;
        if (s.position[i][2] < 1.5 * dp) bottom = std::max(bottom, s.density[i]);
        if (s.position[i][2] > 0.55 - dp) top = std::min(top, s.density[i]);
    }
    // The free surface half a spacing above the top layer (z = 0.56): depth 0.55 at the bottom layer.
    auto rho = [&](double depth) { return 1000 * std::pow(1 + 1000 * 9.81 * depth / s.params.tait_b, 1.0 / 7.0); };
    EXPECT_NEAR(bottom, rho(0.55), 0.01);  // 1002.5
    EXPECT_NEAR(top, rho(0.01), 0.01);
    // Walls under the water start hydrostatic; the floor beside the box and the box, far from it, at rho0.
    for (std::size_t i = 0; i < tank->count; ++i) {
        if (s.position[i][2] > dp / 2) continue;  // the floor
        if (s.position[i][0] > 3.2) {
            ASSERT_NEAR(s.density[i], rho(0.57), 0.01) << i;
        } else if (s.position[i][0] < 1.5) {
            ASSERT_EQ(s.density[i], 1000.0f) << i;
        }
    }
    for (std::size_t i = box->first; i < box->first + box->count; ++i) ASSERT_EQ(s.density[i], 1000.0f);
    EXPECT_NEAR(double(s.params.c0), 20 * std::sqrt(9.81 * 0.55), 1e-4);
    EXPECT_EQ(s.settings.at("case"), case_path("spheric-test2"));
    EXPECT_EQ(s.settings.at("case_hash").size(), 16u);
}

TEST(BoxCase, ShippedCaseFilesLoadAndBuildCoarsely) {
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(SPH_SOURCE_DIR) + "/experiments/cases")) {
        if (entry.path().extension() != ".toml") continue;
        const Scene s = build_scene(case_scene_prefix + entry.path().string(), {{"dp", "0.05"}});
        EXPECT_GT(s.fluid_count(), 0u) << entry.path();
        EXPECT_FALSE(s.bodies.empty()) << entry.path();
        ++files;
    }
    EXPECT_GE(files, 4);
}

class BoxCaseFile : public test::ScratchFolderTest {
protected:
    BoxCaseFile() : ScratchFolderTest("sph_box_case_") {}
    std::string write(const std::string& text) {
        const std::string path = (dir_ / "case.toml").string();
        std::ofstream(path) << text;
        return path;
    }
    // The message of what building the case refused, "" when it built.
    std::string refusal(const std::string& text, const SettingMap& options = {}) {
        const std::string path = write(text);
        try {
            build_scene(case_scene_prefix + path, options);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
};

const std::string tank_text = "[case]\ndp = 0.05\n[case.tank]\nmin = [0, 0, 0]\nmax = [1, 0.5, 0.6]\n";

TEST_F(BoxCaseFile, BadCasesAreRefusedNamingTheFileLineAndKey) {
    const std::string fluid = "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.4, 0.5, 0.3]\n";  // lines 6-8
    struct Bad {
        std::string text, expected;
    };
    const std::vector<Bad> bad = {
        {tank_text + fluid + "colour = \"blue\"\n", ":9: unknown key 'colour' in [[case.fluid]]"},
        {tank_text + "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.4, 0.5, 0.7]\n", ":6: [[case.fluid]] 1: the fluid box"},
        {tank_text + fluid + "[[case.obstacle]]\nname = \"block\"\nmin = [0.3, 0.1, 0]\nmax = [0.5, 0.3, 0.2]\n",
         ":6: [[case.fluid]] 1: the fluid box ('min' [0, 0, 0], 'max' [0.4, 0.5, 0.3]) overlaps obstacle 'block'"},
        {tank_text + fluid + "[[case.obstacle]]\nname = \"thin\"\nmin = [0.6, 0.1, 0]\nmax = [0.62, 0.3, 0.2]\n",
         ":9: [[case.obstacle]] 'thin': obstacle 'thin' is 0.02 m in x ('max' - 'min'), less than one spacing"},
        {tank_text + fluid + "[[case.obstacle]]\nname = \"tank\"\nmin = [0.6, 0.1, 0]\nmax = [0.8, 0.3, 0.2]\n",
         ":10: body name 'tank' is used twice"},
        {tank_text + "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.4, 0.5]\n", ":8: 'max' must be an array of 3 numbers"},
        {tank_text + "[[case.fluid]]\nmin = [0.5, 0, 0]\nmax = [0.4, 0.5, 0.3]\n", ":6: [[case.fluid]] 1: 'max'"},
        {"[case]\ndp = 0.05\nspacing = 2\n", ":3: unknown key 'spacing' in [case]"},
        {tank_text + fluid + "kernel = \"quintic\"\n", ":9: unknown key 'kernel' in [[case.fluid]]"},
        {"[case]\ndp = 0.05\ndomain = [[0, 0, 0], [1, 0.5, 0.6]]\n" + tank_text.substr(17) + fluid,
         ":3: the domain does not hold the particle at [-0.05, -0.05, -0.05]"},
        {"[case]\ndp = 0.05\ndomain_top = 0.55\n" + tank_text.substr(17) + fluid,
         ":3: the domain does not hold the particle at [-0.05, -0.05, 0.6]"},
        {"[case]\ndp = 0.05\ndomain = [[-1, -1, -1], [2, 2, 2]]\ndomain_top = 3\n" + tank_text.substr(17) + fluid,
         ":4: 'domain_top' and 'domain' exclude each other"},
    };
    for (const auto& b : bad) {
        const std::string message = refusal(b.text);
        EXPECT_NE(message.find((dir_ / "case.toml").string() + b.expected), std::string::npos)
            << "expected '" << b.expected << "' in: " << message;
    }
    // A box smaller than one spacing only once the spacing is known: the command line's dp.
    EXPECT_EQ(refusal(tank_text + fluid), "");
    EXPECT_NE(refusal(tank_text + fluid, {{"dp", "0.35"}}).find(":6: [[case.fluid]] 1: the fluid box is 0.3 m in z"),
              std::string::npos);
    // An unknown --set option names the case it was given to.
    EXPECT_NE(refusal(tank_text + fluid, {{"length", "2"}}).find("unknown option 'length'"), std::string::npos);
    // And through the command line: exit 2 before any step.
    std::string message;
    EXPECT_EQ(test::sphbench({"simulate", case_scene_prefix + write(tank_text + fluid + "colour = 1\n"), "--backend",
                              "host", "--steps", "1", "--quiet", "--out", (dir_ / "out").string()},
                             message),
              exit_usage);
    EXPECT_NE(message.find("unknown key 'colour'"), std::string::npos) << message;
}

// [[case.gauges]]: a spec's [[gauges]] keys, read by the same reader (gauge_tables.hpp), named
// in the case's order; bad ones refused naming the file, the line and the key.
TEST_F(BoxCaseFile, CaseGaugesAreReadInOrderAndBadOnesRefusedNamingTheFileLineAndKey) {
    const std::string fluid = "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.4, 0.5, 0.3]\n";  // lines 6-8
    const std::string level = "[[case.gauges]]\nkind = \"water_level\"\nname = \"H1\"\nx = 0.5\ny = 0.25\nevery = 0.01\n";
    const std::string path = write(tank_text + fluid + level +  // the level: lines 9-14
                                   "[[case.gauges]]\nkind = \"pressure\"\nx = 0.2\ny = 0.25\nz = 0.1\nevery = 0.002\n"
                                   "[[case.gauges]]\nkind = \"force\"\nname = \"walls\"\nbody = \"tank\"\nevery = 1\n");
    const std::vector<Gauge> gauges = case_gauges(case_scene_prefix + path);
    ASSERT_EQ(gauges.size(), 3u);
    EXPECT_EQ(gauges[0].name, "H1");
    EXPECT_EQ(gauges[0].kind, GaugeKind::water_level);
    EXPECT_EQ(gauges[0].x, 0.5);
    EXPECT_EQ(gauges[0].every, 0.01);
    EXPECT_EQ(gauges[1].name, "pressure1");  // unnamed: KIND<n>, as a spec's
    EXPECT_EQ(gauges[1].z, 0.1);
    EXPECT_EQ(gauges[2].name, "walls");
    EXPECT_EQ(gauges[2].body, "tank");
    EXPECT_TRUE(case_gauges("tank").empty()) << "a scene of the catalogue has no case gauges";
    EXPECT_TRUE(case_gauges(case_scene_prefix + write(tank_text + fluid)).empty());
    EXPECT_EQ(load_case_file(path).fluids.size(), 1u);  // the gauges are no part of the scene's boxes

    struct Bad {
        std::string text, expected;
    };
    const std::vector<Bad> bad = {
        {level + "colour = \"blue\"\n", ":9: [[case.gauges]] 1: unknown key 'colour' for a water_level gauge"},
        {"[[case.gauges]]\nkind = \"swl\"\nx = 0.5\ny = 0.25\nevery = 0.01\n", ":9: [[case.gauges]] 1: unknown gauge kind 'swl'"},
        {"[[case.gauges]]\nkind = \"pressure\"\nx = 0.5\ny = 0.25\nevery = 0.01\n", ":9: [[case.gauges]] 1: a pressure gauge needs 'z'"},
        {"[[case.gauges]]\nname = \"H1\"\nx = 0.5\ny = 0.25\nevery = 0.01\n", ":9: missing required key 'kind' in [[case.gauges]] 1"},
        {level + level, ":17: gauge name 'H1' is used twice (also at " + (dir_ / "case.toml").string() + ":11)"},
        {"[[case.gauges]]\nkind = \"water_level\"\nx = 0.5\ny = true\nevery = 0.01\n",
         ":12: [[case.gauges]] 1: 'y' must be a number or a string, not a boolean"},
        {level + "[[case.gauges]]\nkind = \"force\"\nbody = \"lid\"\nevery = 1\n",
         ":17: [[case.gauges]] 2: force gauge 'force1': the case has no body 'lid' (its bodies: 'tank')"},
    };
    for (const auto& b : bad) {
        const std::string message = refusal(tank_text + fluid + b.text);
        EXPECT_NE(message.find((dir_ / "case.toml").string() + b.expected), std::string::npos)
            << "expected '" << b.expected << "' in: " << message;
        EXPECT_THROW(case_gauges(case_scene_prefix + (dir_ / "case.toml").string()), InputError) << b.expected;
    }
    EXPECT_NE(refusal("[case]\ndp = 0.05\ngauges = 3\n" + tank_text.substr(17) + fluid)
                  .find(":3: 'gauges' must be [[case.gauges]] tables, not an integer"),
              std::string::npos);
}

TEST_F(BoxCaseFile, FluidIsMadeOnceBesideWallsObstaclesAndOtherFluid) {
    // Two fluid boxes sharing a face and a third inside the first; an obstacle touching the water.
    const Scene s = build_scene(case_scene_prefix + write(tank_text +
                                                          "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [0.4, 0.5, 0.3]\n"
                                                          "[[case.fluid]]\nmin = [0.4, 0, 0]\nmax = [0.6, 0.5, 0.3]\n"
                                                          "[[case.fluid]]\nmin = [0.1, 0.1, 0.1]\nmax = [0.2, 0.2, 0.2]\n"
                                                          "[[case.obstacle]]\nname = \"block\"\nmin = [0.6, 0.1, 0]\n"
                                                          "max = [0.8, 0.3, 0.2]\nlayers = 2\n"),
                                {});
    std::set<std::array<long, 3>> seen;
    for (const auto& x : s.position) {
        const std::array<long, 3> at = {std::lround(x[0] / 0.05), std::lround(x[1] / 0.05), std::lround(x[2] / 0.05)};
        ASSERT_TRUE(seen.insert(at).second) << "two particles at " << x[0] << " " << x[1] << " " << x[2];
    }
    // Fluid: i 1..12 (x 0.05..0.6, the obstacle's face at 0.6 excluded where it stands), j 1..9, k 1..6.
    // (j 2..6 (y 0.1..0.3), k 1..4 (z up to 0.2) at x = 0.6 are the block's).
    EXPECT_EQ(s.fluid_count(), std::size_t(12 * 9 * 6 - 5 * 4));
    // The block: a shell two layers deep inside 0.6..0.8 x 0.1..0.3 x 0..0.2, without the floor.
    const BoundaryBody* block = s.body("block");
    ASSERT_NE(block, nullptr);
    const long all = 5 * 5 * 4, core = 1 * 1 * 2;  // k 1..4; the core: i, j 3, k 1..2 (depth >= 2)
    EXPECT_EQ(block->count, std::size_t(all - core));
}

TEST_F(BoxCaseFile, ClosedTankHasALidAndOpenTankNone) {
    const std::string fluid = "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [1, 0.5, 0.3]\n";
    const Scene open = build_scene(case_scene_prefix + write(tank_text + fluid), {});
    std::string closed_text = tank_text;
    closed_text.insert(closed_text.find("min = [0, 0, 0]"), "open_top = false\n");
    const Scene closed = build_scene(case_scene_prefix + write(closed_text + fluid), {});
    // The lid: the inner points of the top face (i 1..19, j 1..9) and a layer above it over the walls too.
    EXPECT_EQ(closed.n_boundary - open.n_boundary, std::size_t(19 * 9 + 23 * 13));
    double top = 0;
    for (std::size_t i = 0; i < closed.n_boundary; ++i) top = std::max(top, closed.position[i][2]);
    EXPECT_NEAR(top, 0.65, 1e-12);
}

TEST_F(BoxCaseFile, MeshIsFilledInsideTheTank) {
    if (!std::filesystem::exists(std::string(SPH_SOURCE_DIR) + "/../shared/meshes/bunny.obj"))
        GTEST_SKIP() << "the shared meshes are not beside the checkout";
    const std::string mesh = "[[case.mesh]]\nfile = \"bunny.obj\"\nheight = 0.4\nmin = [0.2, 0.05, 0.1]\n";
    const Scene s = build_scene(case_scene_prefix + write(tank_text + mesh), {{"dp", "0.01"}});
    const double scale = 0.4 / 0.616, volume = 0.04848 * scale * scale * scale;  // bunny.obj: 0.616 tall along y
    EXPECT_NEAR(double(s.fluid_count()) * 1e-6, volume, 0.03 * volume);
    for (std::size_t i = s.n_boundary; i < s.size(); ++i) ASSERT_GE(s.position[i][2], 0.1 - 0.01);
    EXPECT_NE(refusal(tank_text + "[[case.mesh]]\nfile = \"bunny.obj\"\nheight = 0.7\nmin = [0.2, 0.05, 0.1]\n",
                      {{"dp", "0.02"}})
                  .find(":6: [[case.mesh]] 'bunny.obj': mesh 'bunny.obj' placed at 'min'"),
              std::string::npos);
}

TEST_F(BoxCaseFile, SpecsRunCaseFilesAndRefuseBadOnesAtLoad) {
    const std::string spec = (dir_ / "spec.toml").string();
    std::ofstream(spec) << "name = \"c\"\nreproduces = \"-\"\nsteps = 2\n[[runs]]\nscene = \"" << case_scene("tank")
                        << "\"\nset = { dp = 0.05 }\n";
    const ExperimentSpec loaded = load_spec(spec);
    EXPECT_EQ(loaded.runs.at(0).label, "tank-1");
    const std::string bad = write(tank_text + "[[case.fluid]]\nmin = [0, 0, 0]\nmax = [2, 0.5, 0.3]\n");
    std::ofstream(spec) << "name = \"c\"\nreproduces = \"-\"\nsteps = 2\n[[runs]]\nscene = \"case:" << bad << "\"\n";
    try {
        load_spec(spec);
        FAIL() << "a case with fluid outside its tank was accepted";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind(spec + ":5: scene 'case:", 0), 0u) << m;
        EXPECT_NE(m.find(bad + ":6: [[case.fluid]] 1"), std::string::npos) << m;
    }
}

// A relative case path in a spec is the spec's folder's: the spec loads from any working directory.
TEST_F(BoxCaseFile, SpecsFindCaseFilesBesideThem) {
    std::filesystem::create_directories(dir_ / "specs" / "cases");
    std::filesystem::copy_file(case_path("tank"), dir_ / "specs" / "cases" / "tank.toml");
    const std::string spec = (dir_ / "specs" / "spec.toml").string();
    std::ofstream(spec) << "name = \"c\"\nreproduces = \"-\"\nsteps = 2\n[[runs]]\nscene = \"case:cases/tank.toml\"\n";
    const ExperimentSpec loaded = load_spec(spec);
    EXPECT_EQ(loaded.runs.at(0).scene, "case:" + (dir_ / "specs" / "cases" / "tank.toml").lexically_normal().string());
    std::ofstream(spec) << "name = \"c\"\nreproduces = \"-\"\nsteps = 2\n[[runs]]\nscene = \"case:tank.toml\"\n";
    EXPECT_THROW(load_spec(spec), InputError);  // not beside the spec: refused at load
}

TEST_F(BoxCaseFile, SimulateRunsACaseFile) {
    std::string message;
    const std::string out = (dir_ / "out").string();
    EXPECT_EQ(test::sphbench({"simulate", case_scene("spheric-test2"), "--set", "dp=0.08", "--backend", "host",
                              "--steps", "3", "--quiet", "--out", out},
                             message),
              exit_ok)
        << message;
    EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(out) / "spheric-test2_steps.csv"));
}

}  // namespace
}  // namespace sph
