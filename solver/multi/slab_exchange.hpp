#pragma once
// Moves particles between the subdomains of an X-slab decomposition: migration (particles
// that left their slab, and slices a balancer handed over, go to their new owner) and the
// ghost refresh (copies of the slices each neighbour reads). Transfers are staged through
// the host (a transport that works for host and GPU subdomains alike).
#include <memory>
#include <vector>

#include "backend/subdomain.hpp"
#include "multi/slab_decomposition.hpp"

namespace sph {

struct ExchangeCounters {
    unsigned long long particles_migrated = 0, ghosts_sent = 0, bytes = 0;
};

class SlabExchange {
public:
    SlabExchange(const GridView& grid, int ghost_slices) : grid_(grid), ghost_slices_(ghost_slices) {}

    // Subdomains must be sorted. `before` is the decomposition their particles were
    // exchanged for, `after` the one to move to (they differ when a balancer moved slices).
    // Afterwards each holds exactly its owned particles (and those that left the domain),
    // unsorted: stale ghosts are dropped, particles outside their new slab go to its owner.
    ExchangeCounters migrate(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& before,
                             const SlabDecomposition& after);
    // Subdomains must be sorted and hold only owned particles. Afterwards each also holds
    // ghost copies of the slices within ghost_slices of its slab, and is sorted, with its
    // owned cells set.
    ExchangeCounters refresh_ghosts(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& slabs);

    std::uint32_t slice_cells() const { return std::uint32_t(grid_.ny) * std::uint32_t(grid_.nz); }
    std::uint32_t first_cell(int slice) const { return std::uint32_t(slice) * slice_cells(); }

private:
    GridView grid_;
    int ghost_slices_;
};

// Bytes one particle occupies in a transfer (position, velocity and density, cell, id).
constexpr std::size_t exchanged_bytes_per_particle = 2 * sizeof(real4) + 2 * sizeof(std::uint32_t);

}  // namespace sph
