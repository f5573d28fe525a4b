// Validation: the dam-break surge front against the experiments, the hydrostatic tank through
// its metric, the metrics' own arithmetic, and bitwise-repeatable runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/error.hpp"
#include "scene_run.hpp"
#include "test_support.hpp"
#include "validation/dambreak_front.hpp"
#include "validation/hydrostatic_pressure.hpp"
#include "validation/reference_series.hpp"

namespace sph {
namespace {

double summary_of(const SceneRunResult& r, const std::string& key) {
    for (const auto& [k, v] : r.validation_summary)
        if (k == key) return v;
    ADD_FAILURE() << "no summary value " << key;
    return std::nan("");
}

// Martin and Moyce's 2.25 in column: Z = 2.292 at T = 1.997 and 2.995 at T = 2.547.
TEST(ReferenceData, InterpolatesInsideAndRefusesToExtrapolate) {
    const ReferenceSeries mm = read_reference_series(find_validation_data("martin_moyce_1952.csv"));
    EXPECT_EQ(mm.x.size(), 15u);
    EXPECT_DOUBLE_EQ(mm.at(1.997), 2.292);
    EXPECT_NEAR(mm.at(0.5 * (1.997 + 2.547)), 0.5 * (2.292 + 2.995), 1e-12);
    EXPECT_TRUE(std::isnan(mm.at(0.5)));   // before the first measurement
    EXPECT_TRUE(std::isnan(mm.at(10.0)));  // after the last
    const ReferenceSeries ko = read_reference_series(find_validation_data("koshizuka_oka_1996.csv"));
    EXPECT_DOUBLE_EQ(ko.at(0.0), 1.0);
    EXPECT_THROW(find_validation_data("no_such_data.csv"), InputError);
}

// A dam break small enough for CI: 10 spacings across the column (a = 0.5 m), 4 across the
// tank's width, run to T = t sqrt(2g/a) = 2.2 (front near Z = 2.5); 12-16 s on one core. The
// mass-threshold front measured an RMS of 0.080 against Koshizuka and Oka, 0.092 against
// Martin and Moyce's 2.25 in column and 0.120 against their 1.125 in one (max 0.13, 0.18,
// 0.22), behind the data at this resolution (fitted offsets -0.10, -0.04, -0.07 in T); the
// particle front read 0.078, 0.092 and 0.119. The tolerance, 0.2 RMS: the experiments
// themselves differ by up to 0.17 in Z for T <= 2.5 (Koshizuka and Oka ahead near T = 1.2,
// behind near T = 2.5), so a run within that spread of them collapses at the experiments'
// speed; a column that stays put (the next test) is more than 0.6 off.
TEST(DambreakValidation, SurgeFrontFollowsMartinMoyceAndKoshizukaOka) {
    SceneRunRequest req;
    req.scene = "dambreak";
    req.scene_options = {{"dp", "0.05"}, {"width", "0.25"}, {"length", "1.6"}, {"height", "1.1"}};
    req.steps = 100000;  // a cap: the end time stops the run
    req.progress = false;
    req.validation = {0.02, 2.2 / std::sqrt(2 * 9.81 / 0.5)};
    const SceneRunResult r = run_scene(req);
    for (const auto& [k, v] : r.validation_summary) std::printf("measured %s = %.4g\n", k.c_str(), v);
    EXPECT_NEAR(summary_of(r, "front_T_end"), 2.2, 0.05);
    EXPECT_LT(summary_of(r, "front_rms_koshizuka_oka"), 0.2);
    EXPECT_LT(summary_of(r, "front_rms_martin_moyce"), 0.2);
    EXPECT_LT(summary_of(r, "front_max_koshizuka_oka"), 0.4);
    EXPECT_LT(summary_of(r, "front_max_martin_moyce"), 0.4);
    EXPECT_LT(summary_of(r, "front_rms_martin_moyce_1125"), 0.2);
    EXPECT_LT(summary_of(r, "front_max_martin_moyce_1125"), 0.4);
    // Whichever way the front is off, a constant shift in T explains most of it.
    EXPECT_LT(summary_of(r, "front_rms_offset_koshizuka_oka"), summary_of(r, "front_rms_koshizuka_oka"));
    EXPECT_LT(std::fabs(summary_of(r, "front_offset_koshizuka_oka")), 0.5);
}

// The same metric on a column that does not move: far outside the tolerance above, so the
// test above can fail.
TEST(DambreakValidation, AColumnThatStaysPutFailsTheTolerance) {
    const Scene s = make_scene("dambreak", {{"dp", "0.05"}, {"width", "0.25"}, {"length", "1.6"}, {"height", "1.1"}});
    Simulation sim(s, SolverOptions{});
    SnapshotData still = sim.snapshot();
    EXPECT_NEAR(surge_front_x(still, s.params.support, 0.0, 3 * s.dp), 0.5, 1e-6);  // float offsets in cells
    auto metric = dambreak_front_metric().make(s);
    const double scale = 1 / std::sqrt(2 * 9.81 / 0.5);
    for (double T = 0; T <= 2.2; T += 0.1) {
        still.time = T * scale;
        metric->sample(still);
    }
    // rms mm, max mm, rms ko, max ko, T end, rms mm 1.125 in, ...
    const std::vector<double> sum = metric->summary();
    ASSERT_EQ(sum.size(), dambreak_front_metric().summary_columns.size());
    EXPECT_GT(sum[2], 0.6);
    EXPECT_GT(sum[0], 0.6);
    EXPECT_GT(sum[5], 0.6);
}

TEST(DambreakValidation, FrontIgnoresASingleDropletAheadOfTheSurge) {
    SnapshotData s;
    auto add = [&](double x, double z) {
        s.position.insert(s.position.end(), {x, 0.0, z});
        s.type.push_back(0);
    };
    add(1.00, 0.02);
    add(1.02, 0.02);  // the surge's edge: two particles together
    add(1.50, 0.02);  // a lone droplet
    add(2.00, 0.50);  // spray above the floor band
    EXPECT_DOUBLE_EQ(surge_front_x(s, 0.04, 0.0, 0.06), 1.02);
}

// A block of water on a floor: lattice particles (spacing dp) whose volume spans x in [0, L]
// (the last particle half a spacing inside), z from dp / 2 up (particles at dp, 2 dp, ...; a
// wall's surface layer would sit at z = 0), y across the line. Its mass-threshold front is L.
struct WaterBlock {
    static constexpr double dp = 0.05;
    static constexpr double mass = 1000 * dp * dp * dp;
    static constexpr double h = 1.7320508075688772 * dp;  // the scenes' h = sqrt(3) dp
    SnapshotData state;
    void add(double x, double y, double z) {
        state.position.insert(state.position.end(), {x, y, z});
        state.type.push_back(0);
    }
    void block(double L, int layers) {
        for (double x = L - 0.5 * dp; x > 0; x -= dp)
            for (int j = -6; j <= 6; ++j)
                for (int k = 1; k <= layers; ++k) add(x, j * dp, k * dp);
    }
    double front() const {
        return mass_threshold_front_x(state, KernelType::wendland, h, mass, dp, floor_front_line(dp, h, 0.0));
    }
};

TEST(DambreakValidation, MassThresholdFrontOfABlockIsItsEnd) {
    WaterBlock w;
    w.block(1.0, 8);
    const double front = w.front();
    std::printf("block ending at 1.0: front %.5f\n", front);
    EXPECT_NEAR(front, 1.0, WaterBlock::dp);
    WaterBlock longer;  // the answer follows the water: a block 4 spacings longer
    longer.block(1.0 + 4 * WaterBlock::dp, 8);
    EXPECT_NEAR(longer.front() - front, 4 * WaterBlock::dp, 1e-9);
    WaterBlock none;  // no water near the line
    none.add(0.5, 0.0, 1.0);
    EXPECT_TRUE(std::isnan(none.front()));
}

// What the experiments would not call the front: a droplet ahead of the water does not move
// it (the particle front of surge_front_x does follow a pair of particles), and neither does a
// film one or two particles thick running on ahead; a tongue three particles deep does.
TEST(DambreakValidation, MassThresholdFrontIgnoresDropletsAndAFilmAhead) {
    constexpr double dp = WaterBlock::dp;
    WaterBlock w;
    w.block(1.0, 8);
    const double front = w.front();
    WaterBlock droplets = w;
    droplets.add(1.0 + 6 * dp, 0.0, dp);
    droplets.add(1.0 + 7 * dp, 0.0, dp);  // a pair: the particle front takes it
    droplets.add(1.0 + 15 * dp, 0.0, 2 * dp);
    EXPECT_DOUBLE_EQ(droplets.front(), front);
    EXPECT_NEAR(surge_front_x(droplets.state, 2 * WaterBlock::h, 0.0, 0.5), 1.0 + 7 * dp, 1e-12);
    auto with_tongue = [&](int layers) {  // a tongue `layers` particles deep from x = 1 to 1.5
        WaterBlock t = w;
        for (double x = 1.0 + 0.5 * dp; x < 1.5; x += dp)
            for (int j = -6; j <= 6; ++j)
                for (int k = 1; k <= layers; ++k) t.add(x, j * dp, k * dp);
        return t.front();
    };
    EXPECT_NEAR(with_tongue(1), 1.0, dp);
    EXPECT_NEAR(with_tongue(2), 1.0, dp);
    EXPECT_NEAR(with_tongue(3), 1.5, dp);
}

// The dam-break scene at rest: the mass-threshold front is the column's width, Z = 1.
TEST(DambreakValidation, MassThresholdFrontOfTheColumnAtRestIsItsWidth) {
    const Scene s = make_scene("dambreak", {{"dp", "0.05"}, {"width", "0.25"}, {"length", "1.6"}, {"height", "1.1"}});
    Simulation sim(s, SolverOptions{});
    auto metric = dambreak_front_metric().make(s);
    const std::vector<double> row = metric->sample(sim.snapshot());  // T, Z, Z_particle, ...
    ASSERT_GE(row.size(), 3u);
    EXPECT_EQ(row[0], 0.0);
    EXPECT_NEAR(row[1], 1.0, 0.5 * s.dp / 0.5);
    EXPECT_NEAR(row[2], 1.0, 1e-6);
}

TEST(DambreakValidation, RefusesAColumnOfTheWrongShape) {
    const Scene s = make_scene("dambreak", {{"dp", "0.1"}, {"column_height", "0.6"}});
    EXPECT_THROW(dambreak_front_metric().make(s), InputError);
}

// The tank of the Hydrostatics test, through its metric: after 400 steps (0.1 s, several
// acoustic crossings) it measured a relative RMS of 1.9% against rho0 g (H - z), the bottom
// layer 47 Pa (2.5%) low (delta-SPH without a correction for the truncated kernel at the free
// surface) and a mean offset of +8 Pa. Bounds: 3% RMS and 4% at the bottom (as the
// Hydrostatics test), so a shifted level or a wrong gradient fails.
TEST(HydrostaticValidation, TankPressureWithinBound) {
    SceneRunRequest req;
    req.scene = "tank";
    req.scene_options = {{"length", "0.15"}, {"width", "0.075"}, {"depth", "0.2"}, {"dp", "0.0125"}};
    req.steps = 400;
    req.progress = false;
    req.validation = {0.02, 0};
    const SceneRunResult r = run_scene(req);
    for (const auto& [k, v] : r.validation_summary) std::printf("measured %s = %.4g\n", k.c_str(), v);
    EXPECT_LT(summary_of(r, "hydro_rel_rms_final"), 0.03);
    EXPECT_LT(std::fabs(summary_of(r, "hydro_bottom_rel_final")), 0.04);
}

TEST(HydrostaticValidation, ExactHydrostaticStateHasNoError) {
    SnapshotData s;
    for (int k = 0; k < 10; ++k) {
        const double z = 0.01 + 0.02 * k;
        s.position.insert(s.position.end(), {0.0, 0.0, z});
        s.type.push_back(0);
        s.pressure.push_back(float(1000 * 9.81 * (0.2 - z)));
    }
    const HydrostaticError e = hydrostatic_error(s, 1000, 9.81, 0.2, 0.02);
    EXPECT_LT(e.rel_rms, 1e-6);
    EXPECT_LT(std::fabs(e.bottom_pa), 1e-3);
}

// Same scene, same seed, same device count: identical particles, bit for bit, on one
// subdomain and on two (what makes a validation number reproducible).
TEST(Repeatability, SameSeedAndDeviceCountGiveIdenticalParticles) {
    const Scene s = test::small_dambreak("0.05");
    for (int devices : {1, 2}) {
        SolverOptions o;
        o.subdomains = devices;
        Simulation a(s, o), b(s, o);
        test::step_both(a, b, 60);
        const SnapshotData sa = a.snapshot(), sb = b.snapshot();
        ASSERT_EQ(sa.id, sb.id) << devices << " device(s)";
        ASSERT_EQ(sa.position.size(), sb.position.size());
        EXPECT_EQ(0, std::memcmp(sa.position.data(), sb.position.data(), sa.position.size() * sizeof(double)));
        EXPECT_EQ(0, std::memcmp(sa.velocity.data(), sb.velocity.data(), sa.velocity.size() * sizeof(float)));
        EXPECT_EQ(0, std::memcmp(sa.density.data(), sb.density.data(), sa.density.size() * sizeof(float)));
        EXPECT_EQ(a.time(), b.time());
    }
}

}  // namespace
}  // namespace sph
