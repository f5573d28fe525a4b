#pragma once
// The X-slab decomposition's whole per-step life (paper section 5): how the particles are
// split at the start, the ghosts dropped before a step, the balancer's move (with the
// per-slice counts it needs), and the one exchange that migrates particles and refreshes
// ghosts. One subdomain is the degenerate case: one slab, and every phase here does nothing,
// so the time loop has one path. Subdomains may be spread over the ranks of an MPI job
// (SubdomainPlacement); this rank's are passed in, and what balancing and statistics need
// from the others comes by allgather, in subdomain order, so every rank decides the same.
#include <memory>
#include <string>
#include <vector>

#include "backend/subdomain.hpp"
#include "multi/load_balancer.hpp"
#include "multi/particle_transport.hpp"
#include "multi/rank_group.hpp"
#include "multi/slab_decomposition.hpp"
#include "multi/slab_exchange.hpp"
#include "multi/subdomain_placement.hpp"

namespace sph {

class SlabDomain {
public:
    // Splits the grid into `subdomains` slabs of about equal particle counts (min width:
    // ghost_slices). Throws InputError for more ranks than subdomains or a grid too narrow.
    SlabDomain(const GridView& grid, int subdomains, int ghost_slices, const std::string& balancer,
               const ParticleArrays& all, RankGroup& ranks);

    int subdomains() const { return slabs_.devices(); }
    bool split() const { return slabs_.devices() > 1; }
    int first_local() const { return placement_.first(ranks_.rank()); }
    int local_count() const { return placement_.count(ranks_.rank()); }
    RankGroup& ranks() const { return ranks_; }

    // This rank's share of `all`: one ParticleArrays per local subdomain (out-of-domain
    // particles go to subdomain 0).
    std::vector<ParticleArrays> local_parts(const ParticleArrays& all) const;
    // After upload: owned cells set and the transport chosen.
    void connect(std::vector<std::unique_ptr<Subdomain>>& subs, TransportKind kind);

    // Drops the ghosts of local subdomain `local` (the exchange needs every particle held once).
    void drop_ghosts(int local, Subdomain& sub) const;
    // Moves slab boundaries from every subdomain's update time of the last step (all
    // subdomains, in order; empty before the first timed step). Returns slices moved.
    int rebalance(std::vector<std::unique_ptr<Subdomain>>& subs, long step, const std::vector<double>& update_times);
    // Migration and ghost refresh in one exchange, for the decomposition as it is now.
    ExchangeCounters exchange(std::vector<std::unique_ptr<Subdomain>>& subs);

    const SlabDecomposition& decomposition() const { return slabs_; }
    // Within a rank the ParticleTransport's; between ranks the RankGroup's messages.
    std::string transport_name() const {
        if (!exchange_) return "";
        if (ranks_.size() == 1) return exchange_->transport().name();
        return exchange_->transport().name() + " within a rank, MPI between ranks";
    }
    const std::string& transport_note() const { return transport_note_; }

private:
    std::uint32_t first_cell(int slice) const { return std::uint32_t(slice) * slice_cells_; }

    GridView grid_;
    std::uint32_t slice_cells_;
    int ghost_slices_;
    RankGroup& ranks_;
    SubdomainPlacement placement_;
    SlabDecomposition slabs_;
    SlabDecomposition exchanged_for_;  // the slabs the particles were last exchanged for
    std::unique_ptr<LoadBalancer> balancer_;
    std::unique_ptr<SlabExchange> exchange_;
    std::string transport_note_;
};

}  // namespace sph
