#include "multi/slab_decomposition.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/error.hpp"

namespace sph {
namespace {

// The bad-input checks shared by both ways of building a decomposition: one sentence each,
// naming the numbers, because these come straight from --devices and the scene's grid.
void check_layout(int slices, int devices, int min_slices) {
    if (devices < 1)
        throw InputError("the slab decomposition needs at least 1 device, got " + std::to_string(devices));
    if (min_slices < 1)
        throw InputError("each slab needs at least 1 cell slice (the ghost depth), got min_slices " +
                         std::to_string(min_slices));
    if (slices < 0 || (long long)devices * min_slices > slices)
        throw InputError(std::to_string(devices) + " devices need at least " +
                         std::to_string((long long)devices * min_slices) + " cell slices of " +
                         std::to_string(min_slices) + " each, the grid has " + std::to_string(slices));
}

}  // namespace

SlabDecomposition::SlabDecomposition(int slices, int devices, int min_slices) : min_slices_(min_slices) {
    check_layout(slices, devices, min_slices);
    // Each width is slices / devices or one more, never below min_slices because
    // devices * min_slices <= slices.
    first_.resize(devices + 1);
    const int base = slices / devices, extra = slices % devices;
    first_[0] = 0;
    for (int d = 0; d < devices; ++d) first_[d + 1] = first_[d] + base + (d < extra ? 1 : 0);
}

SlabDecomposition SlabDecomposition::balanced_by_particles(const std::vector<long long>& particles_per_slice,
                                                           int devices, int min_slices) {
    const int slices = int(particles_per_slice.size());
    check_layout(slices, devices, min_slices);
    std::vector<long long> prefix(slices + 1, 0);  // prefix[i]: particles in slices [0, i)
    for (int i = 0; i < slices; ++i) {
        if (particles_per_slice[i] < 0)
            throw std::invalid_argument("balanced_by_particles: negative particle count in slice " +
                                        std::to_string(i));
        prefix[i + 1] = prefix[i] + particles_per_slice[i];
    }
    const long long total = prefix[slices];
    std::vector<int> first(devices + 1);
    first[0] = 0;
    first[devices] = slices;
    for (int k = 1; k < devices; ++k) {
        // Boundary k may lie in [lo, hi]: after the previous boundary plus min_slices, and
        // early enough that the devices to its right each still get min_slices.
        const int lo = first[k - 1] + min_slices;
        const int hi = slices - (devices - k) * min_slices;
        // Closest prefix sum to total * k / devices, compared exactly in integers
        // (|devices * prefix - k * total|); ties go to the smaller index. The prefix sum is
        // monotone, so scan forward until the error starts growing.
        int best = lo;
        long long best_err = std::llabs(devices * prefix[lo] - k * total);
        for (int b = lo + 1; b <= hi; ++b) {
            const long long err = std::llabs(devices * prefix[b] - k * total);
            if (err < best_err) {
                best = b;
                best_err = err;
            } else if (devices * prefix[b] > k * total) {
                break;
            }
        }
        first[k] = best;
    }
    return SlabDecomposition(std::move(first), min_slices);
}

void SlabDecomposition::check_device(int d) const {
    if (d < 0 || d >= devices())
        throw std::out_of_range("device " + std::to_string(d) + " outside [0, " + std::to_string(devices()) + ")");
}

void SlabDecomposition::check_pair(int pair) const {
    if (pair < 0 || pair >= devices() - 1)
        throw std::out_of_range("device pair " + std::to_string(pair) + " outside [0, " +
                                std::to_string(devices() - 1) + ")");
}

int SlabDecomposition::begin(int d) const {
    check_device(d);
    return first_[d];
}

int SlabDecomposition::end(int d) const {
    check_device(d);
    return first_[d + 1];
}

int SlabDecomposition::owner_of(int slice) const {
    if (slice < 0 || slice >= slices())
        throw std::out_of_range("cell slice " + std::to_string(slice) + " outside [0, " + std::to_string(slices()) + ")");
    // The last first_ entry <= slice names the owner.
    return int(std::upper_bound(first_.begin(), first_.end(), slice) - first_.begin()) - 1;
}

long long SlabDecomposition::particles(int d, const std::vector<long long>& per_slice) const {
    if (int(per_slice.size()) != slices())
        throw std::invalid_argument("particles: " + std::to_string(per_slice.size()) + " slice counts for a grid of " +
                                    std::to_string(slices()) + " slices");
    long long n = 0;
    for (int s = begin(d); s < end(d); ++s) n += per_slice[s];
    return n;
}

bool SlabDecomposition::can_move(int pair, int delta) const {
    check_pair(pair);
    return width(pair) + delta >= min_slices_ && width(pair + 1) - delta >= min_slices_;
}

void SlabDecomposition::move_boundary(int pair, int delta) {
    if (!can_move(pair, delta))
        throw std::invalid_argument("moving the boundary of devices " + std::to_string(pair) + " and " +
                                    std::to_string(pair + 1) + " by " + std::to_string(delta) +
                                    " slices would leave a slab under " + std::to_string(min_slices_) + " slices");
    first_[pair + 1] += delta;
}

int SlabDecomposition::apply_moves(const std::vector<int>& moves) {
    if (int(moves.size()) != devices() - 1)
        throw std::invalid_argument("apply_moves: " + std::to_string(moves.size()) + " moves for " +
                                    std::to_string(devices() - 1) + " device pairs");
    std::vector<int> next = first_;
    for (int p = 0; p < devices() - 1; ++p) next[p + 1] += moves[p];
    for (int d = 0; d < devices(); ++d)
        if (next[d + 1] - next[d] < min_slices_)
            throw std::invalid_argument("apply_moves would leave device " + std::to_string(d) + " with " +
                                        std::to_string(next[d + 1] - next[d]) + " slices, under the minimum of " +
                                        std::to_string(min_slices_));
    int moved = 0;
    for (int m : moves) moved += std::abs(m);
    first_ = std::move(next);
    return moved;
}

}  // namespace sph
