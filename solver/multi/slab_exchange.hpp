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
// one rank go through the ParticleTransport, the others through the RankGroup, their
// particles staged between the subdomains and the messages' host memory by the RankStaging
// (in place on the host, through pinned memory for GPU subdomains).
#include <algorithm>
#include <memory>
#include <vector>

#include "backend/subdomain.hpp"
#include "multi/particle_transport.hpp"
#include "multi/rank_group.hpp"
#include "multi/rank_staging.hpp"
#include "multi/slab_decomposition.hpp"
#include "multi/subdomain_placement.hpp"

namespace sph {

struct ExchangeCounters {
    unsigned long long particles_migrated = 0, ghosts_sent = 0, bytes = 0;
};

// The slices [begin, end) of one slab.
struct SliceRange {
    int begin = 0, end = 0;
    bool empty() const { return end <= begin; }
};

// Paper section 5.3: what subdomain `from` sends, whole and before its inner update, to
// subdomain `to` (from != to): the owned slices of `from` in `now` from which a particle
// moving at most `reach` slices can land in the extended slab of `to` in `next` (the slabs
// after the balancer's move). Empty when none can.
SliceRange boundary_send_slices(const SlabDecomposition& now, const SlabDecomposition& next, int from, int to,
                                int ghost_slices, int reach);
// The boundary area of subdomain g: every slice it sends from, as the slices at its left edge
// [begin, left_end) and at its right edge [right_begin, end) (left_end <= right_begin); the
// inner area [left_end, right_begin) is updated while the boundary area travels.
struct BoundaryArea {
    int begin = 0, left_end = 0, right_begin = 0, end = 0;
};
BoundaryArea boundary_area(const SlabDecomposition& now, const SlabDecomposition& next, int g, int ghost_slices,
                           int reach);

// Verlet lists between rebuilds (no sort, no migration): where the ghosts of one subdomain
// sit on it and on their owner. After a rebuild exchange every holder of a cell holds that
// cell's particles in the same (cell, id) order, and the slabs are at least ghost_slices
// wide, so each of a subdomain's two ghost blocks (the ghost slices of its left neighbour and
// of its right one) is one index range that holds, slot for slot, the particles of one index
// range of the neighbour that owns them. Without a sort both keep their particles until the
// next rebuild, so a refresh is one contiguous copy per such pair.
struct GhostRefresh {
    int from = 0, to = 0;                        // subdomains: the owner, and the holder of the ghosts
    std::uint64_t first = 0, count = 0, offset = 0;  // the owner's first slot; the ghosts' first slot on `to`
};

class SlabExchange {
public:
    // `staging` may be null in a run of one process (nothing goes to another rank).
    SlabExchange(const GridView& grid, int ghost_slices, std::unique_ptr<ParticleTransport> transport,
                 std::unique_ptr<RankStaging> staging = nullptr)
        : grid_(grid), ghost_slices_(ghost_slices), transport_(std::move(transport)), staging_(std::move(staging)) {}

    // `subs` are this rank's subdomains (placement.first(ranks.rank()) onward). They must be
    // sorted and hold no ghosts. Afterwards each holds its owned particles, ghost copies of
    // the slices within ghost_slices of its slab (marked as ghosts) and the particles that
    // left the domain, sorted, with its owned cells set. The counters cover every rank.
    ExchangeCounters exchange(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& slabs,
                              RankGroup& ranks, const SubdomainPlacement& placement);

    // Right after exchange() (the lists are built on that state): each pair's ghost block,
    // for every subdomain (every rank holds the whole plan). The ghosts' count must equal the
    // owner's, which every rank checks (RunError: a bug, not bad input).
    std::vector<GhostRefresh> plan_refresh(std::vector<std::unique_ptr<Subdomain>>& subs,
                                           const SlabDecomposition& slabs, RankGroup& ranks,
                                           const SubdomainPlacement& placement);
    // Copies each owner's current state (Subdomain::state: not the ids, which keep the
    // ghost flags) into the ghost slots of `plan`, made by plan_refresh after the last
    // rebuild exchange, with no sort since: within a rank by the transport, between ranks by
    // MPI messages of the state alone; then each receiver's ghosts_refreshed. overlapped: the
    // transport's begin_delivery, after the owners' boundary areas were marked ready; the
    // caller then finishes it (finish_boundary_exchange) and calls ghosts_refreshed.
    // Counts the ghosts refreshed and their bytes (refreshed_bytes_per_particle).
    ExchangeCounters refresh(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<GhostRefresh>& plan,
                             RankGroup& ranks, const SubdomainPlacement& placement, bool overlapped);

    // The exchange of paper section 5.3, issued after the boundary areas are updated (each
    // marked ready with the transport) and carried under the inner update. `starts[d]` holds
    // cell_start at the slices begin .. end (inclusive) of local subdomain d's slab in `now`,
    // read after its last sort: the boundary slices are sent whole from those ranges, without
    // gathering. `next` is the decomposition the receivers settle for. Counts the particles
    // and bytes that travel (every rank); particles_migrated is known only when they settle.
    ExchangeCounters begin_boundary_exchange(std::vector<std::unique_ptr<Subdomain>>& subs,
                                             const SlabDecomposition& now, const SlabDecomposition& next, int reach,
                                             const std::vector<std::vector<std::uint32_t>>& starts, RankGroup& ranks,
                                             const SubdomainPlacement& placement);
    // Each local receiver of `plan`'s ghosts: Subdomain::ghosts_refreshed, queued after them.
    void ghosts_refreshed(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<GhostRefresh>& plan,
                          RankGroup& ranks, const SubdomainPlacement& placement);
    // Orders each local subdomain's later work after the exchange (no host wait).
    void finish_boundary_exchange(std::vector<std::unique_ptr<Subdomain>>& subs) { transport_->finish_delivery(subs); }
    // After finish, and after subdomain `sub` (global g) dropped its ghosts: appends what it
    // needs of what arrived, sorts, drops what left its extended slab of `next` and sets its
    // owned cells: the state exchange() leaves, bitwise. Returns the received particles it
    // now owns.
    std::size_t settle(Subdomain& sub, int g, const SlabDecomposition& next);
    void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int local) {
        transport_->mark_ready(subs, local);
        if (staging_) staging_->mark_ready(subs, local);
    }
    double last_delivery_ms() { return transport_->last_delivery_ms(); }  // ParticleTransport's

    std::uint32_t slice_cells() const { return std::uint32_t(grid_.ny) * std::uint32_t(grid_.nz); }
    std::uint32_t first_cell(int slice) const { return std::uint32_t(slice) * slice_cells(); }
    // Subdomain k's extended slab in `slabs`: its slab and ghost_slices beyond each face.
    int extended_begin(const SlabDecomposition& slabs, int k) const { return std::max(0, slabs.begin(k) - ghost_slices_); }
    int extended_end(const SlabDecomposition& slabs, int k) const {
        return std::min(slabs.slices(), slabs.end(k) + ghost_slices_);
    }
    const ParticleTransport& transport() const { return *transport_; }

private:
    struct TransferSize {
        std::uint64_t first = 0, count = 0, owned = 0;  // owned: of count, particles the receiver will own
    };
    // Lays out the receive areas for the whole transfer matrix (row g: what g sends, in
    // subdomain order on every rank) and carries this rank's transfers: the transport within
    // the rank (begin_delivery when overlapped, else deliver), MPI messages between ranks
    // (staged out before the message, in after it; in the receive areas when this returns,
    // and each receiver's later work ordered after them).
    ExchangeCounters carry(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<TransferSize>& mine,
                           RankGroup& ranks, const SubdomainPlacement& placement, bool overlapped);
    // The pieces that cross ranks: staged out and packed in order per destination rank, one
    // message exchange, unpacked in order per source rank into the staged receive areas, then
    // delivered in. Every rank calls it (the exchange is collective).
    void send_between_ranks(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<StagedPiece>& outgoing,
                            const std::vector<int>& outgoing_rank, const std::vector<StagedPiece>& incoming,
                            const std::vector<int>& incoming_rank, const std::vector<ParticleSpan>& areas,
                            RankGroup& ranks);

    GridView grid_;
    int ghost_slices_;
    std::unique_ptr<ParticleTransport> transport_;
    std::unique_ptr<RankStaging> staging_;
};

// Bytes one particle occupies in a whole transfer (position, velocity and density, the previous
// step's, cell, id: the five arrays a transfer carries).
constexpr std::size_t exchanged_bytes_per_particle = 3 * sizeof(real4) + 2 * sizeof(std::uint32_t);
// Bytes one ghost's refresh carries (position, velocity and density, the previous step's, cell).
constexpr std::size_t refreshed_bytes_per_particle = 3 * sizeof(real4) + sizeof(std::uint32_t);

}  // namespace sph
