#pragma once
// Dynamic load balancing strategies (paper section 5.2), one concept per class: each looks at
// the per-device update times of the step just done and decides, for every pair of
// neighbouring devices, whether their shared boundary moves one cell slice left, right or not
// at all. The caller applies the decision (SlabDecomposition::apply_moves) and exchanges the
// slices that changed owner.
//
//   none       never moves
//   simple     every step, each pair moves one slice from the slower device to the faster
//   every:K    the simple rule on steps that are multiples of K, nothing on the others
//   threshold  equations 3 to 6: move only when the predicted time difference after the
//              move is smaller than the current one
//   equal-time not the paper's: every boundary goes, in one step, as many slices as needed to
//              give each device the same predicted time (measured time per particle times
//              the per-slice counts); it settles in a few steps where the rules above move
//              one slice a step
#include <memory>
#include <string>
#include <vector>

#include "multi/slab_decomposition.hpp"

namespace sph {

struct BalanceInput {
    const std::vector<double>& device_times;          // per-device update time of the step just done
    const std::vector<long long>& particles_per_slice;  // particles in each cell slice now
    long step;
};

class LoadBalancer {
public:
    virtual ~LoadBalancer();
    // The spec that make_balancer turns back into this balancer ("simple", "every:4", ...).
    virtual std::string name() const = 0;
    // One move per pair (size devices - 1) in slices (+: the boundary moves right, the left
    // device grows); the paper's balancers move -1, 0 or +1. Every move passes can_move, and together they leave every
    // device at least min_slices wide, so they may be applied in any order.
    virtual std::vector<int> decide(const SlabDecomposition& slabs, const BalanceInput& in) = 0;
};

class NoBalancer final : public LoadBalancer {
public:
    std::string name() const override { return "none"; }
    std::vector<int> decide(const SlabDecomposition& slabs, const BalanceInput& in) override;
};

// Paper 5.2's algorithm: for each pair A (left), B (right), the slower gives one slice to the
// faster, every step. Exactly equal times move nothing (the paper's else-branch would move a
// slice from B to A; that would break symmetry for no gain). When both neighbours of a device
// take a slice from it and it would end under min_slices, only the pair with the larger time
// difference moves.
class SimpleBalancer final : public LoadBalancer {
public:
    std::string name() const override { return "simple"; }
    std::vector<int> decide(const SlabDecomposition& slabs, const BalanceInput& in) override;
};

// The simple rule on steps whose number is a multiple of k (step 0 included).
class PeriodicBalancer final : public LoadBalancer {
public:
    explicit PeriodicBalancer(long k);  // InputError for k < 1
    long period() const { return k_; }
    std::string name() const override { return "every:" + std::to_string(k_); }
    std::vector<int> decide(const SlabDecomposition& slabs, const BalanceInput& in) override;

private:
    long k_;
    SimpleBalancer simple_;
};

// Equations 3 to 6. For a pair with times t1 (left) and t2 (right) and particle counts n1, n2,
// each device's time after a move is predicted as t * nc with nc = n_new / n_original, for a
// move of the boundary one slice left (new_time_diff_left) and one slice right
// (new_time_diff_right); threshold = the smaller of the two, and the boundary moves in that
// direction only if |t1 - t2| > threshold.
//
// Two cases the paper leaves open, handled so that the rule reduces to the paper's whenever
// they do not arise:
//  - A device with no particles has no nc; t * nc is written t + (n_new - n_original) * rate
//    with rate = t / n_original, and an empty device borrows its neighbour's rate.
//  - A boundary slice with no particles changes no count, so the paper's prediction would
//    never move it and the boundary would stall at an empty gap however large the imbalance.
//    The prediction instead uses the first occupied slice the donor could give (looking past
//    empty ones, within what it may give up); the boundary then walks over the empty slices,
//    one a step, toward that slice.
class ThresholdBalancer final : public LoadBalancer {
public:
    std::string name() const override { return "threshold"; }
    std::vector<int> decide(const SlabDecomposition& slabs, const BalanceInput& in) override;
};

// Places every boundary where the predicted times balance. A slice's predicted time is its
// particle count times the time per particle its current owner measured (t_d / n_d; an empty
// device borrows the mean rate of all), so it needs no model of the cost, only the measurement
// the threshold rule uses. Boundary k goes to the slice edge whose prefix of predicted time is
// closest to k / devices of the total, within the room min_slices leaves; it moves only if
// its current edge misses that target by more than `tolerance` of the mean device time, which
// keeps measurement noise below the tolerance from moving anything (no oscillation). Where the
// cost per particle varies along X the first placement is off by the difference in rates; the
// next steps, measuring the new slabs, correct it (a fixed-point iteration on the rates).
class EqualTimeBalancer final : public LoadBalancer {
public:
    static constexpr double default_tolerance = 0.01;
    explicit EqualTimeBalancer(double tolerance = default_tolerance);  // InputError outside [0, 0.5)
    std::string name() const override;
    std::vector<int> decide(const SlabDecomposition& slabs, const BalanceInput& in) override;

private:
    double tolerance_;
};

// "none", "simple", "every:K" (K >= 1), "threshold", "equal-time" or "equal-time:F" (F the
// tolerance as a fraction of the mean device time, default 0.01); anything else is an
// InputError.
std::unique_ptr<LoadBalancer> make_balancer(const std::string& spec);

}  // namespace sph
