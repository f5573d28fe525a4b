#pragma once
// The X-slab decomposition's whole per-step life (paper section 5): how the particles are
// split at the start, the ghosts dropped before a step, the balancer's move (with the
// per-slice counts it needs), and the one exchange that migrates particles and refreshes
// ghosts. One subdomain is the degenerate case: one slab, and every phase here does nothing,
// so the time loop has one path. Subdomains may be spread over the ranks of an MPI job
// (SubdomainPlacement); this rank's are passed in, and what balancing and statistics need
// from the others comes by allgather, in subdomain order, so every rank decides the same.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "backend/subdomain.hpp"
#include "multi/load_balancer.hpp"
#include "multi/particle_transport.hpp"
#include "multi/rank_group.hpp"
#include "multi/rank_staging.hpp"
#include "multi/slab_decomposition.hpp"
#include "multi/slab_exchange.hpp"
#include "multi/subdomain_placement.hpp"

namespace sph {

class SlabDomain {
public:
    // Splits the grid into `subdomains` slabs of about equal particle counts (min width:
    // ghost_slices). Throws InputError for more ranks than subdomains or a grid too narrow.
    // overlap: paper section 5.3's order (below) instead of balance-then-exchange at the start
    // of each step; the particles are the same either way, bitwise.
    SlabDomain(const GridView& grid, int subdomains, int ghost_slices, const std::string& balancer,
               const ParticleArrays& all, RankGroup& ranks, bool overlap = false);

    int subdomains() const { return slabs_.devices(); }
    bool split() const { return slabs_.devices() > 1; }
    int first_local() const { return placement_.first(ranks_.rank()); }
    int local_count() const { return placement_.count(ranks_.rank()); }
    RankGroup& ranks() const { return ranks_; }

    // This rank's share of `all`: one ParticleArrays per local subdomain (out-of-domain
    // particles go to subdomain 0).
    std::vector<ParticleArrays> local_parts(const ParticleArrays& all) const;
    // After upload: owned cells set, the transport chosen, and the staging of particles that
    // go to other ranks (rank_transport: choose_rank_transport's, with its note).
    void connect(std::vector<std::unique_ptr<Subdomain>>& subs, TransportKind kind,
                 const RankTransportChoice& rank_transport = {});

    // Drops the ghosts of local subdomain `local` (the exchange needs every particle held once).
    void drop_ghosts(int local, Subdomain& sub) const;
    // Moves slab boundaries from every subdomain's update time of the last step (all
    // subdomains, in order; empty before the first timed step). Returns slices moved.
    int rebalance(std::vector<std::unique_ptr<Subdomain>>& subs, long step, const std::vector<double>& update_times);
    // Migration and ghost refresh in one exchange, for the decomposition as it is now.
    ExchangeCounters exchange(std::vector<std::unique_ptr<Subdomain>>& subs);
    // Verlet lists: right after exchange() (or settled()), where each ghost block sits on its
    // holder and on its owner (SlabExchange::plan_refresh); then each step until the next
    // exchange, refresh() copies the owners' state into those ghosts, in place: no drop, no
    // balance, no sort, so the lists built on the exchanged state stay valid. Overlapping,
    // begin_refresh() instead of begin_exchange(), after the boundary areas of
    // set_refresh_reach() are updated: nothing is left in flight to settle.
    void plan_refresh(std::vector<std::unique_ptr<Subdomain>>& subs);
    ExchangeCounters refresh(std::vector<std::unique_ptr<Subdomain>>& subs);
    ExchangeCounters begin_refresh(std::vector<std::unique_ptr<Subdomain>>& subs);
    const std::vector<GhostRefresh>& refresh_plan() const { return refresh_plan_; }

    // Paper section 5.3, when overlapping: the step's one exchange is issued during the
    // update and settled at the start of the next step.
    //   start of step: if exchange_in_flight(): drop_ghosts, then settle(d) for each local
    //     subdomain (appends what arrived, sorts), then settled();
    //   read_slices() after that; the forces; decide_balance() (on the host while the forces
    //     run: the repartition delayed into the update, taking effect with this step's
    //     exchange); the statistics;
    //   set_reach(), then per subdomain: advance the cells of update_order(d)[0] and [1] (the
    //     boundary area), boundary_ready(d), advance [2] (the inner area); begin_exchange()
    //     sends the boundary areas whole while the inner areas are updated; finish_exchange()
    //     orders the next step's work after it.
    // With Verlet lists a step settles, reads the slices and (after its statistics, when the
    // next step rebuilds) balances only before a rebuild; a step followed by none calls
    // set_refresh_reach() and begin_refresh() in place of set_reach() and begin_exchange().
    bool overlapping() const { return split() && overlap_; }
    bool exchange_in_flight() const { return in_flight_; }
    void settle(int local, Subdomain& sub);
    ExchangeCounters settled();  // the counters of the exchange just settled (every rank)
    // cell_start at the owned slices of each local subdomain, after its sort.
    void read_slices(std::vector<std::unique_ptr<Subdomain>>& subs);
    // The move for the exchange at the end of this step, from the last step's update times
    // (all subdomains, in order; empty before the first timed step). Those were measured with
    // measured_particles owned per subdomain, on the slabs before this step's settle, which
    // may have moved since: the balancer is given each time scaled to the particles owned
    // now (the same time per particle), so that a move already made is not made again.
    int decide_balance(long step, const std::vector<double>& update_times,
                       const std::vector<std::size_t>& measured_particles);
    // How far (metres along x) any particle can have moved since the last sort: how many
    // slices the boundary areas must hold beyond the neighbours' extended slabs.
    void set_reach(double max_displacement);
    // A refresh's boundary areas: exactly the slices the neighbours hold as ghosts.
    void set_refresh_reach() { reach_ = 0; }
    struct CellRange {
        std::uint32_t begin = 0, end = 0;
    };
    // The left and right boundary cells, then the inner cells, of local subdomain `local`:
    // disjoint, together its owned cells.
    std::array<CellRange, 3> update_order(int local) const;
    void boundary_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int local) { exchange_->mark_ready(subs, local); }
    void begin_exchange(std::vector<std::unique_ptr<Subdomain>>& subs);
    void finish_exchange(std::vector<std::unique_ptr<Subdomain>>& subs);
    int reach() const { return reach_; }
    // The copies of the exchange begun last, timed where they ran (CUDA events on the
    // transport's streams; waits for them); -1 where the host's time of begin_exchange is theirs.
    double last_transfer_ms() { return exchange_ ? exchange_->last_delivery_ms() : -1; }

    const SlabDecomposition& decomposition() const { return slabs_; }
    // Within a rank the ParticleTransport's; between ranks the RankGroup's messages.
    std::string transport_name() const {
        if (!exchange_) return "";
        if (ranks_.size() == 1) return exchange_->transport().name();
        return exchange_->transport().name() + " within a rank, MPI between ranks (" + rank_transport_name() + ")";
    }
    const std::string& transport_note() const { return transport_note_; }
    // How particles between ranks travel ("" in one process): "host-memory", "staged-pinned".
    std::string rank_transport_name() const { return exchange_ ? rank_transport_label(rank_transport_.kind) : ""; }
    const std::string& rank_transport_note() const { return rank_transport_.note; }

private:
    std::uint32_t first_cell(int slice) const { return std::uint32_t(slice) * slice_cells_; }
    std::vector<long long> per_slice_counts() const;  // from read_slices, summed over ranks
    ExchangeCounters refresh_ghosts(std::vector<std::unique_ptr<Subdomain>>& subs, bool overlapped);

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
    RankTransportChoice rank_transport_;
    bool overlap_ = false;
    bool in_flight_ = false;
    int reach_ = 1;
    std::vector<std::vector<std::uint32_t>> starts_;  // read_slices: per local subdomain
    std::vector<GhostRefresh> refresh_plan_;           // of the last exchange, when planned
    bool refresh_planned_ = false;
    bool refresh_in_flight_ = false;                   // begun, not finished
    ExchangeCounters sent_;                            // of the exchange in flight
    unsigned long long migrated_ = 0;                  // settled so far on this rank
};

}  // namespace sph
