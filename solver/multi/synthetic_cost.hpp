#pragma once
// A deterministic stand-in for per-device update times, for the load-balancing tests and the
// harness's dry runs: a device's time is the sum over its slices of
//     particles_per_slice[s] * cost_per_particle[s]
// (a per-slice cost, because in SPH the cost of a particle depends on how many neighbours it
// has, which varies with density along X), optionally times (1 + noise_fraction * u) with u
// uniform in [-1, 1) drawn from a seeded std::mt19937, to mimic the step-to-step jitter of
// measured times (the paper's Fig. 4: within 1 % to 3 %). std::mt19937's output sequence is
// fixed by the standard and u is computed from it directly (not through a distribution, whose
// algorithm is implementation-defined), so the same seed gives the same times everywhere.
#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "multi/slab_decomposition.hpp"

namespace sph {

class SyntheticCost {
public:
    explicit SyntheticCost(std::vector<double> cost_per_particle, double noise_fraction = 0.0,
                           std::uint32_t seed = 20240521u)
        : cost_(std::move(cost_per_particle)), noise_(noise_fraction), rng_(seed) {
        if (noise_ < 0 || noise_ >= 1)
            throw std::invalid_argument("SyntheticCost: noise fraction must be in [0, 1), got " +
                                        std::to_string(noise_));
    }

    int slices() const { return int(cost_.size()); }
    double noise_fraction() const { return noise_; }

    // The time of slice s alone, without noise.
    double slice_time(int s, const std::vector<long long>& per_slice) const {
        return double(per_slice.at(s)) * cost_.at(s);
    }

    // Device times without noise: what balancing should equalise.
    std::vector<double> exact_times(const SlabDecomposition& slabs, const std::vector<long long>& per_slice) const {
        check(slabs, per_slice);
        std::vector<double> t(slabs.devices(), 0.0);
        for (int d = 0; d < slabs.devices(); ++d)
            for (int s = slabs.begin(d); s < slabs.end(d); ++s) t[d] += slice_time(s, per_slice);
        return t;
    }

    // Device times as a run would measure them: exact times with noise. Advances the
    // generator by one draw per device when noise is on.
    std::vector<double> measure(const SlabDecomposition& slabs, const std::vector<long long>& per_slice) {
        std::vector<double> t = exact_times(slabs, per_slice);
        if (noise_ > 0)
            for (double& x : t) x *= 1.0 + noise_ * (2.0 * (double(rng_()) / 4294967296.0) - 1.0);
        return t;
    }

    // The largest single-slice time: the granularity below which slice moves cannot balance.
    double largest_slice_time(const std::vector<long long>& per_slice) const {
        double m = 0;
        for (int s = 0; s < slices(); ++s) m = std::max(m, slice_time(s, per_slice));
        return m;
    }

    double total_time(const std::vector<long long>& per_slice) const {
        double sum = 0;
        for (int s = 0; s < slices(); ++s) sum += slice_time(s, per_slice);
        return sum;
    }

private:
    void check(const SlabDecomposition& slabs, const std::vector<long long>& per_slice) const {
        if (slabs.slices() != slices() || int(per_slice.size()) != slices())
            throw std::invalid_argument("SyntheticCost: " + std::to_string(slices()) + " slice costs, " +
                                        std::to_string(per_slice.size()) + " slice counts, a grid of " +
                                        std::to_string(slabs.slices()) + " slices");
    }

    std::vector<double> cost_;
    double noise_;
    std::mt19937 rng_;
};

}  // namespace sph
