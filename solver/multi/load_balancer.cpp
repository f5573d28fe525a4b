#include "multi/load_balancer.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <algorithm>
#include <stdexcept>

#include "core/error.hpp"

namespace sph {
namespace {

// The times and counts come from the solver, not the user: a size mismatch is a caller bug.
void check_input(const SlabDecomposition& slabs, const BalanceInput& in) {
    if (int(in.device_times.size()) != slabs.devices())
        throw std::invalid_argument("load balancer: " + std::to_string(in.device_times.size()) +
                                    " device times for " + std::to_string(slabs.devices()) + " devices");
    if (int(in.particles_per_slice.size()) != slabs.slices())
        throw std::invalid_argument("load balancer: " + std::to_string(in.particles_per_slice.size()) +
                                    " slice counts for " + std::to_string(slabs.slices()) + " slices");
}

// Makes a set of per-pair moves safe to apply in any order. A move that can_move refuses is
// dropped; then a device that both neighbours take a slice from (its left pair moves right,
// its right pair moves left) and that would end under min_slices keeps only the move of larger
// `urgency` (ties keep the left pair's). Dropping a move that shrinks a device only stops its
// neighbour from growing, so no other device is pushed under the minimum: one pass suffices.
std::vector<int> keep_min_slices(const SlabDecomposition& slabs, std::vector<int> moves,
                                 const std::vector<double>& urgency) {
    const int pairs = slabs.devices() - 1;
    for (int p = 0; p < pairs; ++p)
        if (moves[p] != 0 && !slabs.can_move(p, moves[p])) moves[p] = 0;
    for (int d = 1; d + 1 < slabs.devices(); ++d) {
        const bool loses_left = moves[d - 1] > 0, loses_right = moves[d] < 0;
        if (loses_left && loses_right && slabs.width(d) - 2 < slabs.min_slices()) {
            if (urgency[d] > urgency[d - 1])
                moves[d - 1] = 0;
            else
                moves[d] = 0;
        }
    }
    return moves;
}

// The donor's particles in the slice it would give when its boundary with the pair moves one
// slice: the first occupied slice from the boundary inward, among the slices it may give up
// (all but its min_slices). 0 when all of those are empty or it may give none.
long long slice_to_give(const SlabDecomposition& slabs, int donor, bool gives_right_edge,
                        const std::vector<long long>& per_slice) {
    const int spare = slabs.width(donor) - slabs.min_slices();
    for (int i = 0; i < spare; ++i) {
        const int s = gives_right_edge ? slabs.end(donor) - 1 - i : slabs.begin(donor) + i;
        if (per_slice[s] > 0) return per_slice[s];
    }
    return 0;
}

}  // namespace

LoadBalancer::~LoadBalancer() = default;

std::vector<int> NoBalancer::decide(const SlabDecomposition& slabs, const BalanceInput& in) {
    check_input(slabs, in);
    return std::vector<int>(slabs.devices() - 1, 0);
}

std::vector<int> SimpleBalancer::decide(const SlabDecomposition& slabs, const BalanceInput& in) {
    check_input(slabs, in);
    const int pairs = slabs.devices() - 1;
    std::vector<int> moves(pairs, 0);
    std::vector<double> urgency(pairs, 0);
    for (int p = 0; p < pairs; ++p) {
        const double ta = in.device_times[p], tb = in.device_times[p + 1];
        // A slower: A gives its last slice to B, the boundary moves left. B slower: right.
        moves[p] = ta > tb ? -1 : ta < tb ? +1 : 0;
        urgency[p] = std::fabs(ta - tb);
    }
    return keep_min_slices(slabs, std::move(moves), urgency);
}

PeriodicBalancer::PeriodicBalancer(long k) : k_(k) {
    if (k < 1) throw InputError("load balancer every:K needs K >= 1, got " + std::to_string(k));
}

std::vector<int> PeriodicBalancer::decide(const SlabDecomposition& slabs, const BalanceInput& in) {
    check_input(slabs, in);
    if (in.step % k_ != 0) return std::vector<int>(slabs.devices() - 1, 0);
    return simple_.decide(slabs, in);
}

std::vector<int> ThresholdBalancer::decide(const SlabDecomposition& slabs, const BalanceInput& in) {
    check_input(slabs, in);
    const auto& per_slice = in.particles_per_slice;
    const int pairs = slabs.devices() - 1;
    std::vector<int> moves(pairs, 0);
    std::vector<double> urgency(pairs, 0);
    const double never = std::numeric_limits<double>::infinity();
    for (int p = 0; p < pairs; ++p) {
        const double t1 = in.device_times[p], t2 = in.device_times[p + 1];
        const long long n1 = slabs.particles(p, per_slice), n2 = slabs.particles(p + 1, per_slice);
        if (n1 + n2 == 0) continue;  // nothing to move, nothing to predict with
        // t * nc = t + (n_new - n_original) * t / n_original; an empty device borrows the
        // neighbour's time per particle.
        const double rate1 = n1 > 0 ? t1 / double(n1) : t2 / double(n2);
        const double rate2 = n2 > 0 ? t2 / double(n2) : t1 / double(n1);
        // Equation 3: the boundary one slice left, the left device gives c particles.
        double diff_left = never;
        if (slabs.can_move(p, -1)) {
            const double c = double(slice_to_give(slabs, p, true, per_slice));
            diff_left = std::fabs((t1 - c * rate1) - (t2 + c * rate2));
        }
        // Equation 4: the boundary one slice right, the right device gives c particles.
        double diff_right = never;
        if (slabs.can_move(p, +1)) {
            const double c = double(slice_to_give(slabs, p + 1, false, per_slice));
            diff_right = std::fabs((t1 + c * rate1) - (t2 - c * rate2));
        }
        // Equation 6, and the move only when it is predicted to reduce the difference.
        const double threshold = std::fmin(diff_left, diff_right);
        const double now = std::fabs(t1 - t2);
        if (!(now > threshold)) continue;
        if (diff_left < diff_right)
            moves[p] = -1;
        else if (diff_right < diff_left)
            moves[p] = +1;
        else
            moves[p] = t1 > t2 ? -1 : +1;  // equal predictions: from the slower to the faster
        urgency[p] = now - threshold;
    }
    return keep_min_slices(slabs, std::move(moves), urgency);
}

EqualTimeBalancer::EqualTimeBalancer(double tolerance) : tolerance_(tolerance) {
    if (!(tolerance >= 0 && tolerance < 0.5))
        throw InputError("load balancer equal-time:F needs a tolerance F in [0, 0.5), got " + std::to_string(tolerance));
}

std::string EqualTimeBalancer::name() const {
    if (tolerance_ == default_tolerance) return "equal-time";
    std::ostringstream s;
    s << "equal-time:" << tolerance_;
    return s.str();
}

std::vector<int> EqualTimeBalancer::decide(const SlabDecomposition& slabs, const BalanceInput& in) {
    check_input(slabs, in);
    const int devices = slabs.devices(), slices = slabs.slices(), min = slabs.min_slices();
    std::vector<int> moves(devices - 1, 0);
    // Time per particle per device; an empty device (or one that measured nothing) borrows
    // the mean rate, so that slices it would take are not predicted free.
    double all_time = 0;
    long long all_particles = 0;
    for (int d = 0; d < devices; ++d) {
        all_time += in.device_times[d];
        all_particles += slabs.particles(d, in.particles_per_slice);
    }
    if (all_particles == 0 || !(all_time > 0)) return moves;
    const double mean_rate = all_time / double(all_particles);
    std::vector<double> prefix(slices + 1, 0.0);  // predicted time of slices [0, s)
    for (int d = 0; d < devices; ++d) {
        const long long n = slabs.particles(d, in.particles_per_slice);
        const double rate = n > 0 && in.device_times[d] > 0 ? in.device_times[d] / double(n) : mean_rate;
        for (int s = slabs.begin(d); s < slabs.end(d); ++s)
            prefix[s + 1] = double(in.particles_per_slice[s]) * rate;
    }
    for (int s = 0; s < slices; ++s) prefix[s + 1] += prefix[s];
    const double total = prefix[slices], mean = total / devices;
    int previous = 0;  // boundary k - 1 as decided
    for (int k = 1; k < devices; ++k) {
        const int lo = previous + min, hi = slices - (devices - k) * min;
        const double target = mean * k;
        const int now = slabs.boundaries()[k];
        int best = now;
        if (now < lo || now > hi || std::fabs(prefix[now] - target) > tolerance_ * mean) {
            best = std::clamp(now, lo, hi);
            for (int b = lo; b <= hi; ++b)  // ties go to the edge nearest the current one
                if (std::fabs(prefix[b] - target) < std::fabs(prefix[best] - target) ||
                    (std::fabs(prefix[b] - target) == std::fabs(prefix[best] - target) &&
                     std::abs(b - now) < std::abs(best - now)))
                    best = b;
        }
        moves[k - 1] = best - now;
        previous = best;
    }
    return moves;
}

std::unique_ptr<LoadBalancer> make_balancer(const std::string& spec) {
    if (spec == "none") return std::make_unique<NoBalancer>();
    if (spec == "equal-time") return std::make_unique<EqualTimeBalancer>();
    const std::string equal_time = "equal-time:";
    if (spec.rfind(equal_time, 0) == 0) {
        const std::string f = spec.substr(equal_time.size());
        std::size_t used = 0;
        double tolerance = -1;
        try {
            tolerance = std::stod(f, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (f.empty() || used != f.size() || !(tolerance >= 0 && tolerance < 0.5))
            throw InputError("load balancer '" + spec + "': equal-time:F needs a tolerance F in [0, 0.5), a fraction "
                             "of the mean device time");
        return std::make_unique<EqualTimeBalancer>(tolerance);
    }
    if (spec == "simple") return std::make_unique<SimpleBalancer>();
    if (spec == "threshold") return std::make_unique<ThresholdBalancer>();
    const std::string every = "every:";
    if (spec.rfind(every, 0) == 0) {
        const std::string k = spec.substr(every.size());
        // Digits only (no sign, no spaces, no trailing text) and small enough for a long.
        bool digits = !k.empty() && k.size() <= 12;
        for (char ch : k) digits = digits && ch >= '0' && ch <= '9';
        if (!digits || std::stol(k) < 1)
            throw InputError("load balancer '" + spec + "': every:K needs a whole number K >= 1");
        return std::make_unique<PeriodicBalancer>(std::stol(k));
    }
    throw InputError("unknown load balancer '" + spec + "': use none, simple, every:K (K >= 1), threshold or equal-time[:F]");
}

}  // namespace sph
