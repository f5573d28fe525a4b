// Search calibration times all eight strategies and keeps the fastest it timed.
#include <gtest/gtest.h>

#include "search_calibration.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

TEST(SearchCalibration, TimesEveryStrategyAndPicksTheFastest) {
    const Calibration c = calibrate_search(test::small_dambreak("0.05"), SolverOptions{}, 3);
    ASSERT_EQ(c.trials.size(), 8u);
    const CalibrationTrial* fastest = &c.trials.front();
    for (const auto& t : c.trials) {
        EXPECT_GT(t.median_step_ms, 0);
        if (t.median_step_ms < fastest->median_step_ms) fastest = &t;
    }
    EXPECT_EQ(c.best.cells_per_support, fastest->search.cells_per_support);
    EXPECT_EQ(c.best.merge, fastest->search.merge);
}

}  // namespace
}  // namespace sph
