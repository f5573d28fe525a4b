// The time-offset fit of the dam-break front (solver/validation/time_offset_fit.hpp) on
// synthetic fronts whose lead over the "data" is known: a constant shift, and a lead that grows.
#include <gtest/gtest.h>

#include <cmath>

#include "validation/time_offset_fit.hpp"

namespace sph {
namespace {

// A smooth surge front in Z against T (accelerating, like the experiments').
double surge(double T) { return 1 + 0.3 * T + 0.25 * T * T; }

// The "data": dense points from T = 0.5 (after any shift, so the column's rest does not enter).
ReferenceSeries data_points() {
    ReferenceSeries d;
    for (double T = 0.5; T <= 2.5 + 1e-9; T += 0.05) {
        d.x.push_back(T);
        d.y.push_back(surge(T));
    }
    return d;
}

// Our front sampled as the metric samples it (every 0.0626 in T, from 0), at (1 + stretch) T + lead.
FrontSeries computed(double lead, double stretch) {
    FrontSeries f;
    for (int i = 0; i <= 40; ++i) {
        const double T = 0.0626 * i;
        f.T.push_back(T);
        f.Z.push_back(surge((1 + stretch) * T + lead));
    }
    return f;
}

TEST(TimeOffsetFit, RecoversAKnownShift) {
    const ReferenceSeries data = data_points();
    for (double lead : {0.175, 0.3, -0.12}) {
        const FrontSeries ours = computed(lead, 0.0);
        const TimeOffsetFit fit = fit_time_offset(ours, data);
        EXPECT_NEAR(fit.offset, lead, 1e-3) << "lead " << lead;
        EXPECT_LT(fit.rms, 2e-3) << "lead " << lead;
        EXPECT_GT(delayed_front_rms(ours, data, 0.0), 0.1) << "lead " << lead;  // unshifted, it is off
        const LeadTrend trend = lead_trend(ours, data);
        EXPECT_NEAR(trend.slope, 0.0, 1e-3) << "lead " << lead;
        EXPECT_NEAR(trend.intercept, lead, 1e-3) << "lead " << lead;
    }
}

// Our front running 10% fast: it reaches the data's Z(T) at T / 1.1, a lead of T (0.1 / 1.1)
// that grows with T; a constant shift fits it worse than it fits a shifted front.
TEST(TimeOffsetFit, ReportsALeadThatGrows) {
    const ReferenceSeries data = data_points();
    const FrontSeries ours = computed(0.0, 0.1);
    const LeadTrend trend = lead_trend(ours, data);
    EXPECT_NEAR(trend.slope, 0.1 / 1.1, 1e-3);
    EXPECT_NEAR(trend.intercept, 0.0, 1e-3);
    const TimeOffsetFit fit = fit_time_offset(ours, data);
    EXPECT_GT(fit.offset, 0.05);
    EXPECT_GT(fit.rms, 0.01);
}

TEST(TimeOffsetFit, DelayedFrontHoldsStillBeforeItsFirstSampleAndEndsAtItsLast) {
    FrontSeries f;
    f.T = {0.0, 1.0, 2.0};
    f.Z = {1.0, 2.0, 4.0};
    EXPECT_DOUBLE_EQ(f.at(-0.5), 1.0);
    EXPECT_DOUBLE_EQ(f.at(1.5), 3.0);
    EXPECT_TRUE(std::isnan(f.at(2.5)));
    ReferenceSeries d;
    d.x = {0.0, 2.0};
    d.y = {1.0, 3.0};
    EXPECT_DOUBLE_EQ(delayed_front_rms(f, d, 0.0), std::sqrt(1.0 / 3.0));  // residuals 0, 0, 1
    EXPECT_TRUE(std::isnan(fit_time_offset(FrontSeries{}, d).offset));
}

}  // namespace
}  // namespace sph
