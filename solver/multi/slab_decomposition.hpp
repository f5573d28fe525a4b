#pragma once
// The X-slab decomposition of the cell grid among devices (paper section 5.1). The grid has
// `slices` cell slices along X (a slice = all cells with one x index); device d owns slices
// [begin(d), end(d)). Every slab keeps at least `min_slices` slices (the ghost depth in
// slices), so that the ghost region a device needs from a neighbour always lies inside that
// immediate neighbour and never reaches past it.
//
// Load balancing moves the boundary between two neighbouring devices ("pair" p is the pair of
// devices p and p + 1, whose boundary is boundaries()[p + 1]) by whole slices.
#include <utility>
#include <vector>

namespace sph {

class SlabDecomposition {
public:
    // An even split: each device gets slices / devices slices, the first slices % devices
    // devices one more. Throws InputError for devices < 1, min_slices < 1 or a grid too small
    // to give every device min_slices slices.
    SlabDecomposition(int slices, int devices, int min_slices);

    // A split whose particle counts are as equal as possible: boundary k is the slice edge
    // whose particle prefix sum is closest to k / devices of the total, kept far enough from
    // its neighbours that every slab has min_slices slices. particles_per_slice.size() is the
    // number of slices.
    static SlabDecomposition balanced_by_particles(const std::vector<long long>& particles_per_slice,
                                                   int devices, int min_slices);

    int devices() const { return int(first_.size()) - 1; }
    int slices() const { return first_.back(); }
    int min_slices() const { return min_slices_; }
    int begin(int d) const;
    int end(int d) const;
    int width(int d) const { return end(d) - begin(d); }
    // The device that owns `slice`.
    int owner_of(int slice) const;
    // The particles of device d: the sum of per_slice over its slices.
    long long particles(int d, const std::vector<long long>& per_slice) const;

    // Whether the boundary of pair (devices pair and pair + 1) may move by delta slices
    // (+: right, so device pair grows) and leave both devices at least min_slices wide.
    bool can_move(int pair, int delta) const;
    // Moves one boundary; a move that can_move refuses is a caller bug (std::invalid_argument).
    void move_boundary(int pair, int delta);
    // Applies one move per pair (a LoadBalancer's decision, size devices - 1). Checks the
    // resulting widths first, so either every move happens or none (std::invalid_argument).
    // Returns how many slices changed owner (the sum of |move|).
    int apply_moves(const std::vector<int>& moves);

    // devices + 1 entries: device d owns [boundaries()[d], boundaries()[d + 1]); the first is
    // 0 and the last is slices().
    const std::vector<int>& boundaries() const { return first_; }

    friend bool operator==(const SlabDecomposition&, const SlabDecomposition&) = default;

private:
    SlabDecomposition(std::vector<int> first, int min_slices) : first_(std::move(first)), min_slices_(min_slices) {}
    void check_device(int d) const;
    void check_pair(int pair) const;

    std::vector<int> first_;
    int min_slices_ = 1;
};

}  // namespace sph
