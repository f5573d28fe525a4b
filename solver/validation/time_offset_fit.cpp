#include "validation/time_offset_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sph {
namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double FrontSeries::at(double t) const {
    if (T.empty() || !(t <= T.back())) return nan;
    if (t <= T.front()) return Z.front();
    const std::size_t i = std::size_t(std::upper_bound(T.begin(), T.end(), t) - T.begin());  // T[i-1] <= t < T[i]
    if (i >= T.size()) return Z.back();
    const double w = (t - T[i - 1]) / (T[i] - T[i - 1]);
    return Z[i - 1] + w * (Z[i] - Z[i - 1]);
}

double delayed_front_rms(const FrontSeries& ours, const ReferenceSeries& data, double offset) {
    double sum2 = 0;
    long n = 0;
    for (double t : ours.T) {
        const double measured = data.at(t), computed = ours.at(t - offset);
        if (!std::isfinite(measured) || !std::isfinite(computed)) continue;
        sum2 += (computed - measured) * (computed - measured);
        ++n;
    }
    return n ? std::sqrt(sum2 / double(n)) : nan;
}

TimeOffsetFit fit_time_offset(const FrontSeries& ours, const ReferenceSeries& data, double lowest, double highest) {
    // A scan first: the RMS of a piecewise linear front need not be convex in the offset.
    constexpr double step = 1e-3;
    TimeOffsetFit best{nan, nan};
    const long points = long(std::floor((highest - lowest) / step + 1e-9)) + 1;
    for (long k = 0; k < points; ++k) {
        const double offset = lowest + step * double(k), rms = delayed_front_rms(ours, data, offset);
        if (std::isfinite(rms) && !(rms >= best.rms)) best = {offset, rms};
    }
    if (!std::isfinite(best.offset)) return best;
    double lo = std::max(lowest, best.offset - step), hi = std::min(highest, best.offset + step);
    const double ratio = 0.5 * (std::sqrt(5.0) - 1);
    for (int iteration = 0; iteration < 40; ++iteration) {
        const double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
        const double ra = delayed_front_rms(ours, data, a), rb = delayed_front_rms(ours, data, b);
        if (!(rb < ra)) hi = b;
        else lo = a;
    }
    const double refined = 0.5 * (lo + hi), rms = delayed_front_rms(ours, data, refined);
    if (std::isfinite(rms) && rms <= best.rms) best = {refined, rms};
    return best;
}

LeadTrend lead_trend(const FrontSeries& ours, const ReferenceSeries& data) {
    std::vector<double> t, lead;
    for (double T_i : ours.T) {
        const double z = data.at(T_i);
        if (!std::isfinite(z) || ours.Z.empty() || !(ours.Z.front() < z)) continue;
        for (std::size_t k = 1; k < ours.T.size(); ++k) {
            if (!(ours.Z[k] >= z)) continue;
            const double reached =
                ours.T[k - 1] + (ours.T[k] - ours.T[k - 1]) * (z - ours.Z[k - 1]) / (ours.Z[k] - ours.Z[k - 1]);
            t.push_back(T_i);
            lead.push_back(T_i - reached);
            break;
        }
    }
    const long n = long(t.size());
    if (n < 2) return {nan, nan, n};
    double mt = 0, ml = 0;
    for (long i = 0; i < n; ++i) mt += t[i], ml += lead[i];
    mt /= double(n);
    ml /= double(n);
    double stt = 0, stl = 0;
    for (long i = 0; i < n; ++i) stt += (t[i] - mt) * (t[i] - mt), stl += (t[i] - mt) * (lead[i] - ml);
    if (!(stt > 0)) return {nan, nan, n};
    const double slope = stl / stt;
    return {ml - slope * mt, slope, n};
}

}  // namespace sph
