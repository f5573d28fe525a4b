#include "validation/dambreak_front.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.hpp"
#include "validation/reference_series.hpp"

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

class DambreakFrontMetric : public ValidationMetric {
public:
    explicit DambreakFrontMetric(const Scene& scene)
        : martin_moyce_(read_reference_series(find_validation_data("martin_moyce_1952.csv"))),
          koshizuka_oka_(read_reference_series(find_validation_data("koshizuka_oka_1996.csv"))) {
        a_ = setting(scene, "column_width");
        const double b = setting(scene, "column_height");
        if (std::fabs(b / a_ - 2.0) > 0.01)
            throw InputError("the dam-break front metric needs column_height = 2 x column_width (Martin and Moyce's "
                             "n^2 = 2); this scene has " + scene.settings.at("column_height") + " and " +
                             scene.settings.at("column_width"));
        support_ = scene.params.support;
        g_ = -double(scene.params.gravity.z);
        if (!(g_ > 0)) throw InputError("the dam-break front metric needs gravity > 0");
    }

    std::vector<double> sample(const SnapshotData& state) override {
        // The wall's surface layer sits at z = 0 and x = 0 and the fluid starts one spacing
        // in, so the water's volume reaches half a spacing beyond the front particle and
        // starts half a spacing off the wall: the front's distance is the particle's x. The
        // band, z < a, is the lower half of the column (see surge_front_x).
        const double x = surge_front_x(state, support_, 0.0, a_);
        const double T = state.time * std::sqrt(2 * g_ / a_), Z = x / a_;
        const double zm = martin_moyce_.at(T), zk = koshizuka_oka_.at(T);
        mm_.add(Z - zm);
        ko_.add(Z - zk);
        last_T_ = T;
        return {T, Z, zm, zk};
    }

    std::vector<double> summary() const override {
        return {mm_.rms(), mm_.largest, ko_.rms(), ko_.largest, last_T_};
    }

private:
    ReferenceSeries martin_moyce_, koshizuka_oka_;
    double a_ = 0, support_ = 0, g_ = 0, last_T_ = nan;
    Deviation mm_, ko_;
};

}  // namespace

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
    "surge front Z = x/a against T = t sqrt(2g/a): Martin and Moyce (1952) and Koshizuka and Oka (1996)",
    {"T", "Z", "Z_martin_moyce", "Z_koshizuka_oka"},
    {"front_rms_martin_moyce", "front_max_martin_moyce", "front_rms_koshizuka_oka", "front_max_koshizuka_oka",
     "front_T_end"},
    [](const Scene& scene) { return std::make_unique<DambreakFrontMetric>(scene); },
    };
    return info;
}

}  // namespace sph
