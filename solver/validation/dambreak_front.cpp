#include "validation/dambreak_front.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/water_mass_threshold.hpp"
#include "validation/reference_series.hpp"
#include "validation/time_offset_fit.hpp"

namespace sph {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

double setting(const Scene& s, const std::string& key) {
    const auto it = s.settings.find(key);
    if (it == s.settings.end()) throw InputError("scene '" + s.name + "' does not record its option '" + key + "'");
    return std::stod(it->second);
}

// RMS and largest absolute difference against one reference, over the samples it covers.
struct Deviation {
    double sum2 = 0, largest = nan;
    long n = 0;
    void add(double d) {
        if (!std::isfinite(d)) return;
        sum2 += d * d;
        ++n;
        if (!(std::fabs(d) <= largest)) largest = std::fabs(d);
    }
    double rms() const { return n ? std::sqrt(sum2 / double(n)) : nan; }
};

// The data sets, as the summary keys name them.
struct FrontDataSet {
    const char* key;
    const char* file;
};
constexpr FrontDataSet front_data_sets[] = {{"martin_moyce", "martin_moyce_1952.csv"},
                                            {"martin_moyce_1125", "martin_moyce_1952_a1125.csv"},
                                            {"koshizuka_oka", "koshizuka_oka_1996.csv"}};
constexpr std::size_t front_data_set_count = sizeof(front_data_sets) / sizeof(front_data_sets[0]);

std::vector<std::string> front_sample_columns() {
    std::vector<std::string> c = {"T", "Z", "Z_particle"};
    for (const auto& d : front_data_sets) c.push_back(std::string("Z_") + d.key);
    return c;
}

// The first five as the metric had them (tests and older results read them by position).
std::vector<std::string> front_summary_columns() {
    std::vector<std::string> c = {"front_rms_martin_moyce", "front_max_martin_moyce", "front_rms_koshizuka_oka",
                                  "front_max_koshizuka_oka", "front_T_end", "front_rms_martin_moyce_1125",
                                  "front_max_martin_moyce_1125"};
    for (const char* what : {"front_offset_", "front_rms_offset_", "front_rms_published_offset_", "front_lead_slope_",
                             "front_particle_rms_"})
        for (const auto& d : front_data_sets) c.push_back(what + std::string(d.key));
    return c;
}

class DambreakFrontMetric : public ValidationMetric {
public:
    explicit DambreakFrontMetric(const Scene& scene) : kernel_(scene.kernel) {
        for (const auto& d : front_data_sets) data_.push_back(read_reference_series(find_validation_data(d.file)));
        a_ = setting(scene, "column_width");
        const double b = setting(scene, "column_height");
        if (std::fabs(b / a_ - 2.0) > 0.01)
            throw InputError("the dam-break front metric needs column_height = 2 x column_width (Martin and Moyce's "
                             "n^2 = 2); this scene has " + scene.settings.at("column_height") + " and " +
                             scene.settings.at("column_width"));
        support_ = scene.params.support;
        h_ = scene.params.h;
        mass_ = scene.params.mass;
        dp_ = scene.dp;
        g_ = -double(scene.params.gravity.z);
        if (!(g_ > 0)) throw InputError("the dam-break front metric needs gravity > 0");
        line_ = floor_front_line(dp_, h_, 0.5 * setting(scene, "width"));  // the middle of the tank
    }

    std::vector<double> sample(const SnapshotData& state) override {
        // The wall's surface layer sits at x = 0 and the fluid starts one spacing in, so the
        // water's volume starts half a spacing off the wall: the front's distance from the wall
        // is the water's edge less dp / 2 (and, for the particle front, the particle's x, half a
        // spacing behind the edge). The particle front's band, z < a, is the lower half of the
        // column (see surge_front_x).
        const double edge = mass_threshold_front_x(state, kernel_, h_, mass_, dp_, line_);
        const double particle = surge_front_x(state, support_, 0.0, a_);
        const double T = state.time * std::sqrt(2 * g_ / a_), Z = (edge - 0.5 * dp_) / a_, Zp = particle / a_;
        std::vector<double> row = {T, Z, Zp};
        for (std::size_t d = 0; d < front_data_set_count; ++d) {
            const double measured = data_[d].at(T);
            mass_error_[d].add(Z - measured);
            particle_error_[d].add(Zp - measured);
            row.push_back(measured);
        }
        if (std::isfinite(Z)) {
            front_.T.push_back(T);
            front_.Z.push_back(Z);
        }
        last_T_ = T;
        return row;
    }

    std::vector<double> summary() const override {
        const Deviation &mm = mass_error_[0], &mm1125 = mass_error_[1], &ko = mass_error_[2];
        std::vector<double> s = {mm.rms(), mm.largest, ko.rms(), ko.largest, last_T_, mm1125.rms(), mm1125.largest};
        std::vector<double> offset, rms_offset, rms_published, slope, particle_rms;
        for (std::size_t d = 0; d < front_data_set_count; ++d) {
            const TimeOffsetFit fit = fit_time_offset(front_, data_[d]);
            offset.push_back(fit.offset);
            rms_offset.push_back(fit.rms);
            rms_published.push_back(delayed_front_rms(front_, data_[d], published_gate_offset_T));
            slope.push_back(lead_trend(front_, data_[d]).slope);
            particle_rms.push_back(particle_error_[d].rms());
        }
        for (const auto* group : {&offset, &rms_offset, &rms_published, &slope, &particle_rms})
            s.insert(s.end(), group->begin(), group->end());
        return s;
    }

private:
    KernelType kernel_;
    std::vector<ReferenceSeries> data_;
    double a_ = 0, support_ = 0, h_ = 0, mass_ = 0, dp_ = 0, g_ = 0, last_T_ = nan;
    FrontLine line_;
    Deviation mass_error_[front_data_set_count], particle_error_[front_data_set_count];
    FrontSeries front_;
};

// The kernel-summed fluid mass along the line, then its last crossing of the threshold. Only
// fluid within the support of the line contributes, each to the samples within its support.
template <class Kernel>
double mass_front_with(const SnapshotData& s, const Kernel& kernel, double support, double particle_mass, double dp,
                       const FrontLine& line) {
    const std::size_t n = s.type.size();
    const double support2 = support * support;
    std::vector<std::size_t> near;
    double furthest = -1;
    for (std::size_t j = 0; j < n; ++j) {
        if (s.type[j] != 0) continue;
        const double* p = &s.position[3 * j];
        if (!std::isfinite(p[0]) || !(std::fabs(p[1] - line.y) < support) || !(std::fabs(p[2] - line.z) < support))
            continue;
        near.push_back(j);
        furthest = std::max(furthest, p[0]);
    }
    if (near.empty() || !(furthest > -support)) return nan;
    const std::size_t count = std::size_t(std::ceil((furthest + support) / line.spacing)) + 2;
    std::vector<double> mass(count, 0.0);
    for (std::size_t j : near) {
        const double* p = &s.position[3 * j];
        const double across2 = (p[1] - line.y) * (p[1] - line.y) + (p[2] - line.z) * (p[2] - line.z);
        const long first = std::max(0L, long(std::ceil((p[0] - support) / line.spacing)));
        const long last = std::min(long(count) - 1, long(std::floor((p[0] + support) / line.spacing)));
        for (long k = first; k <= last; ++k) {
            const double dx = line.spacing * double(k) - p[0], r2 = dx * dx + across2;
            if (r2 < support2) mass[std::size_t(k)] += particle_mass * double(kernel.w(real(std::sqrt(r2))));
        }
    }
    return last_threshold_crossing(count, 0.0, line.spacing, water_mass_threshold(particle_mass, dp),
                                   [&](std::size_t k) { return mass[k]; });
}

}  // namespace

FrontLine floor_front_line(double dp, double h, double y) { return {y, dp + h, 0.25 * dp}; }

double mass_threshold_front_x(const SnapshotData& state, KernelType kernel, double h, double particle_mass,
                              double dp, const FrontLine& line) {
    if (!(line.spacing > 0)) throw InputError("the mass-threshold front needs a sample spacing above 0");
    if (kernel == KernelType::wendland)
        return mass_front_with(state, WendlandC2(real(h)), 2 * h, particle_mass, dp, line);
    return mass_front_with(state, CubicSpline(real(h)), 2 * h, particle_mass, dp, line);
}

double surge_front_x(const SnapshotData& s, double radius, double floor_z, double band) {
    const std::size_t n = s.type.size();
    std::vector<std::size_t> floor;
    for (std::size_t i = 0; i < n; ++i)
        if (s.type[i] == 0 && std::isfinite(s.position[3 * i]) && s.position[3 * i + 2] - floor_z < band)
            floor.push_back(i);
    std::sort(floor.begin(), floor.end(), [&](std::size_t a, std::size_t b) { return s.position[3 * a] > s.position[3 * b]; });
    const double r2 = radius * radius;
    for (std::size_t i : floor) {  // usually the first or second candidate passes
        for (std::size_t j = 0; j < n; ++j) {
            if (j == i || s.type[j] != 0) continue;
            double d2 = 0;
            for (int k = 0; k < 3; ++k) d2 += (s.position[3 * j + k] - s.position[3 * i + k]) * (s.position[3 * j + k] - s.position[3 * i + k]);
            if (d2 < r2) return s.position[3 * i];
        }
    }
    return nan;
}

const ValidationMetricInfo& dambreak_front_metric() {
    static const ValidationMetricInfo info = {
    "dambreak",
    "surge front Z = x/a (mass threshold on the floor) against T = t sqrt(2g/a): Martin and Moyce (1952, a = 2.25 "
    "and 1.125 in) and Koshizuka and Oka (1996), with fitted time offsets",
    front_sample_columns(),
    front_summary_columns(),
    [](const Scene& scene) { return std::make_unique<DambreakFrontMetric>(scene); },
    };
    return info;
}

}  // namespace sph
