#pragma once
// Moves particles between the subdomains of an X-slab decomposition in one exchange per step:
// each subdomain d must end up with every particle of its extended slab (its own slices plus
// ghost_slices on each side). Before the exchange every particle is held by exactly one
// subdomain (ghosts were dropped), so each sends the particles it holds in every other
// subdomain's extended slab and keeps those in its own: particles that left a slab (and
// slices a balancer handed over) reach their new owner, and ghost copies reach the neighbours
// that read them, in the same transfer. This is the paper's "send all potential migrating
// particles" (section 5.3) taken one step further: migration and the ghost refresh are one
// message per pair of subdomains, and no gather kernel is needed since a sort by cell makes
// each extended slab one contiguous range.
//
// Subdomains may live on several ranks (SubdomainPlacement). Every rank learns the whole
// matrix of transfer sizes by one allgather, so receive areas are laid out by sender in
// subdomain order on every rank exactly as in one process; transfers between subdomains of
// one rank go through the ParticleTransport, the others through the RankGroup.
#include <memory>
#include <vector>

#include "backend/subdomain.hpp"
#include "multi/particle_transport.hpp"
#include "multi/rank_group.hpp"
#include "multi/slab_decomposition.hpp"
#include "multi/subdomain_placement.hpp"

namespace sph {

struct ExchangeCounters {
    unsigned long long particles_migrated = 0, ghosts_sent = 0, bytes = 0;
};

class SlabExchange {
public:
    SlabExchange(const GridView& grid, int ghost_slices, std::unique_ptr<ParticleTransport> transport)
        : grid_(grid), ghost_slices_(ghost_slices), transport_(std::move(transport)) {}

    // `subs` are this rank's subdomains (placement.first(ranks.rank()) onward). They must be
    // sorted and hold no ghosts. Afterwards each holds its owned particles, ghost copies of
    // the slices within ghost_slices of its slab (marked as ghosts) and the particles that
    // left the domain, sorted, with its owned cells set. The counters cover every rank.
    ExchangeCounters exchange(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& slabs,
                              RankGroup& ranks, const SubdomainPlacement& placement);

    std::uint32_t slice_cells() const { return std::uint32_t(grid_.ny) * std::uint32_t(grid_.nz); }
    std::uint32_t first_cell(int slice) const { return std::uint32_t(slice) * slice_cells(); }
    const ParticleTransport& transport() const { return *transport_; }

private:
    GridView grid_;
    int ghost_slices_;
    std::unique_ptr<ParticleTransport> transport_;
};

// Bytes one particle occupies in a transfer (position, velocity and density, cell, id).
constexpr std::size_t exchanged_bytes_per_particle = 2 * sizeof(real4) + 2 * sizeof(std::uint32_t);

}  // namespace sph
