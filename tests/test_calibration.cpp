// Search calibration times all eight cell searches and both Verlet lists, and keeps the
// fastest it timed; where the lists are refused, it times the cell searches and says why.
#include <gtest/gtest.h>

#include "search_calibration.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

TEST(SearchCalibration, TimesEveryStrategyAndPicksTheFastest) {
    const Calibration c = calibrate_search(test::small_dambreak("0.05"), SolverOptions{}, 3);
    ASSERT_EQ(c.trials.size(), 10u);
    EXPECT_TRUE(c.verlet_skipped.empty()) << c.verlet_skipped;
    EXPECT_TRUE(c.trials[8].search.verlet && c.trials[9].search.verlet);
    EXPECT_EQ(c.trials[9].search.cells_per_support, 2);
    const CalibrationTrial* fastest = &c.trials.front();
    for (const auto& t : c.trials) {
        EXPECT_GT(t.mean_step_ms, 0);
        if (t.mean_step_ms < fastest->mean_step_ms) fastest = &t;
    }
    EXPECT_EQ(c.best.cells_per_support, fastest->search.cells_per_support);
    EXPECT_EQ(c.best.merge, fastest->search.merge);
    EXPECT_EQ(c.best.verlet, fastest->search.verlet);
    EXPECT_EQ(c.best.rebuild_every, 0);  // the run rebuilds when its flow needs it, not every 5 steps
}

// Lists on several host subdomains, overlapped (the default), are timed like one subdomain's.
TEST(SearchCalibration, TimesTheListsOnSeveralSubdomains) {
    SolverOptions two;
    two.subdomains = 2;
    const Calibration c = calibrate_search(test::small_dambreak("0.05"), two, 3);
    ASSERT_EQ(c.trials.size(), 10u);
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
