#pragma once
// How far a computed front is ahead of measured data in time. The experiments' clock starts
// when the gate starts to open, and the gate takes time to clear the water, so a computed front
// (released at once) leads by some offset in T even if the flow after release were exact.
// Sign convention everywhere here: a positive offset or lead means the computed front is ahead
// (it reached a position earlier than the data did).
#include <vector>

#include "validation/reference_series.hpp"

namespace sph {

// A computed front's history: T increasing, Z its position at each T.
struct FrontSeries {
    std::vector<double> T, Z;
    // Linear between samples; before the first sample the first sample's Z (the column stands
    // until it is released); NaN after the last sample.
    double at(double T_value) const;
};

// RMS over the samples T_i of `ours` where the data are defined of Z_ours(T_i - offset) -
// Z_data(T_i): the computed front delayed by `offset`. offset = 0 gives the plain RMS. Samples
// whose delayed time falls after the last computed sample (offset < 0) are left out. NaN when
// no sample is left.
double delayed_front_rms(const FrontSeries& ours, const ReferenceSeries& data, double offset);

struct TimeOffsetFit {
    double offset;  // the delay in T that minimises delayed_front_rms (> 0: ours leads)
    double rms;     // delayed_front_rms at that offset
};

// The offset within [lowest, highest] that minimises delayed_front_rms: a scan every 1e-3,
// then a golden-section search around the best point of the scan. NaN when the series do not
// overlap.
TimeOffsetFit fit_time_offset(const FrontSeries& ours, const ReferenceSeries& data, double lowest = -1.0,
                              double highest = 1.0);

// Whether the lead is a constant shift: at each sample T_i where the data are defined, the
// lead is T_i minus the first time the computed front reached Z_data(T_i) (samples whose data
// Z the computed front had from the start, or never reached, are left out); a least-squares
// line lead = intercept + slope T through them. A constant shift has slope 0; slope > 0 means
// the computed front pulls further ahead as it goes. NaN when fewer than two leads are defined.
struct LeadTrend {
    double intercept, slope;
    long samples;
};
LeadTrend lead_trend(const FrontSeries& ours, const ReferenceSeries& data);

}  // namespace sph
