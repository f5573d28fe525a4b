// Search calibration times all eight cell searches and the Verlet lists at four layouts and
// skins, weighing each list trial's rebuild and listed steps by the run's expected steps
// between rebuilds, and keeps the cheapest; where the lists are refused, it times the cell
// searches and says why.
#include <gtest/gtest.h>

#include "search_calibration.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

TEST(SearchCalibration, TimesEveryStrategyAndPicksTheCheapestRun) {
    const Scene s = test::small_dambreak("0.05");
    const Calibration c = calibrate_search(s, SolverOptions{}, 3);
    ASSERT_EQ(c.trials.size(), 12u);
    EXPECT_TRUE(c.verlet_skipped.empty()) << c.verlet_skipped;
    const CalibrationTrial* cheapest = &c.trials.front();
    for (std::size_t k = 0; k < c.trials.size(); ++k) {
        const CalibrationTrial& t = c.trials[k];
        EXPECT_EQ(t.search.verlet, k >= 8) << k;
        EXPECT_GT(t.mean_step_ms, 0);
        if (t.search.verlet) {
            // Both kinds of step measured, and the mean is the model's, not the trial's own
            // (which rebuilt every verlet_trial_rebuild_every steps).
            EXPECT_GT(t.rebuild_step_ms, 0);
            EXPECT_GT(t.listed_step_ms, 0);
            EXPECT_DOUBLE_EQ(t.rebuild_interval, expected_rebuild_interval(s.params, s.cfl, t.search.skin));
            EXPECT_DOUBLE_EQ(t.mean_step_ms, predicted_step_ms(t.rebuild_step_ms, t.listed_step_ms, t.rebuild_interval));
        }
        if (t.mean_step_ms < cheapest->mean_step_ms) cheapest = &t;
    }
    EXPECT_EQ(c.trials[9].search.cells_per_support, 2);
    EXPECT_EQ(c.trials[9].search.skin, 0.05);
    EXPECT_EQ(c.trials[11].search.skin, 0.2);
    EXPECT_EQ(c.best.cells_per_support, cheapest->search.cells_per_support);
    EXPECT_EQ(c.best.merge, cheapest->search.merge);
    EXPECT_EQ(c.best.verlet, cheapest->search.verlet);
    EXPECT_EQ(c.best.skin, cheapest->search.skin);
    EXPECT_EQ(c.best.rebuild_every, 0);  // the run rebuilds when its own flow needs it
}

// The model on numbers worked by hand: a flow at c0 / 10 moves 0.1 CFL h / 1.1 a step, so at
// CFL 0.2 the lists hold 55 x skin steps (the dam break of issue 25 rebuilt every 7.7 steps
// at skin 0.1 over its whole event: this is the cautious side of it).
TEST(SearchCalibration, ExpectedRebuildIntervalAndPredictedStep) {
    PhysicsParams p;
    p.h = 0.01f;
    p.c0 = 30;
    p.support = 2 * p.h;
    EXPECT_NEAR(expected_rebuild_interval(p, 0.2, 0.1), 5.5, 1e-5);
    EXPECT_NEAR(expected_rebuild_interval(p, 0.2, 0.2), 11.0, 1e-5);
    EXPECT_NEAR(expected_rebuild_interval(p, 0.1, 0.1), 11.0, 1e-5);  // half the step, twice the steps
    EXPECT_EQ(expected_rebuild_interval(p, 0.2, 0.001), 1.0);        // at least every step
    // A rebuild of 4 ms and a listed step of 1.4 ms every 5.5 steps: 1.4 + 2.6 / 5.5.
    EXPECT_NEAR(predicted_step_ms(4.0, 1.4, 5.5), 1.4 + 2.6 / 5.5, 1e-12);
    EXPECT_EQ(predicted_step_ms(4.0, 1.4, 0.5), 4.0);  // rebuilding every step costs a rebuild
}

// Lists on several host subdomains, overlapped (the default), are timed like one subdomain's.
TEST(SearchCalibration, TimesTheListsOnSeveralSubdomains) {
    SolverOptions two;
    two.subdomains = 2;
    const Calibration c = calibrate_search(test::small_dambreak("0.05"), two, 3);
    ASSERT_EQ(c.trials.size(), 12u);
    EXPECT_TRUE(c.verlet_skipped.empty()) << c.verlet_skipped;
}

// Where the lists are refused (particle shifting), the cell searches are timed and the
// refusal is said.
TEST(SearchCalibration, TimesTheCellSearchesWhereVerletListsAreRefused) {
    Scene shifted = test::small_dambreak("0.05");
    shifted.params.shift = 0.5;
    const Calibration c = calibrate_search(shifted, SolverOptions{}, 3);
    ASSERT_EQ(c.trials.size(), 8u);
    EXPECT_NE(c.verlet_skipped.find("shifting"), std::string::npos) << c.verlet_skipped;
    EXPECT_FALSE(c.best.verlet);
}

}  // namespace
}  // namespace sph
