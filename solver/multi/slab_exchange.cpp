#include "multi/slab_exchange.hpp"

#include <algorithm>
#include <cstring>

#include "core/error.hpp"

namespace sph {
namespace {

// A transfer's arrays, one after another, in host memory (pos, velrho, velrho_prev, cell, id;
// a null one is not carried): what a message between ranks carries. The spans are host
// memory (a host subdomain's own, or what the RankStaging staged).
void pack(Bytes& out, const ParticleSpan& src, std::size_t count) {
    auto put = [&](const auto* p) {
        if (!p) return;
        const std::size_t at = out.size(), bytes = count * sizeof(*p);
        out.resize(at + bytes);
        std::memcpy(out.data() + at, p, bytes);
    };
    put(src.pos);
    put(src.velrho);
    put(src.velrho_prev);
    put(src.cell);
    put(src.id);
}

std::size_t unpack(const Bytes& in, std::size_t at, const ParticleSpan& dst, std::size_t count) {
    auto get = [&](auto* p) {
        if (!p) return;
        const std::size_t bytes = count * sizeof(*p);
        if (at + bytes > in.size()) throw RunError("an MPI particle message is shorter than its transfer sizes");
        std::memcpy(p, in.data() + at, bytes);
        at += bytes;
    };
    get(dst.pos);
    get(dst.velrho);
    get(dst.velrho_prev);
    get(dst.cell);
    get(dst.id);
    return at;
}

}  // namespace

SliceRange boundary_send_slices(const SlabDecomposition& now, const SlabDecomposition& next, int from, int to,
                                int ghost_slices, int reach) {
    const int ext_begin = std::max(0, next.begin(to) - ghost_slices);
    const int ext_end = std::min(next.slices(), next.end(to) + ghost_slices);
    const int lo = std::max(now.begin(from), ext_begin - reach);
    const int hi = std::min(now.end(from), ext_end + reach);
    return {lo, std::max(lo, hi)};
}

BoundaryArea boundary_area(const SlabDecomposition& now, const SlabDecomposition& next, int g, int ghost_slices,
                           int reach) {
    BoundaryArea a{now.begin(g), now.begin(g), now.end(g), now.end(g)};
    for (int k = 0; k < now.devices(); ++k) {
        if (k == g) continue;
        const SliceRange r = boundary_send_slices(now, next, g, k, ghost_slices, reach);
        if (r.empty()) continue;
        if (k < g) a.left_end = std::max(a.left_end, r.end);
        else a.right_begin = std::min(a.right_begin, r.begin);
    }
    // Narrow slabs: the two edges' areas meet and there is no inner area.
    a.right_begin = std::max(a.right_begin, a.left_end);
    return a;
}

ExchangeCounters SlabExchange::exchange(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& slabs,
                                        RankGroup& ranks, const SubdomainPlacement& placement) {
    const int n = slabs.devices();
    const int first_local = placement.first(ranks.rank()), local = int(subs.size());
    auto ext_begin = [&](int k) { return extended_begin(slabs, k); };
    auto ext_end = [&](int k) { return extended_end(slabs, k); };

    // Where each extended slab (and the owned part inside it) starts and ends in each sorted
    // subdomain of this rank: one read of cell_start per subdomain.
    std::vector<TransferSize> mine(std::size_t(local) * n);
    for (int d = 0; d < local; ++d) {
        std::vector<std::uint32_t> cells;
        for (int k = 0; k < n; ++k)
            for (int slice : {ext_begin(k), slabs.begin(k), slabs.end(k), ext_end(k)}) cells.push_back(first_cell(slice));
        const std::vector<std::uint32_t> at = subs[d]->cell_starts(cells);
        for (int k = 0; k < n; ++k) {
            if (k == first_local + d) continue;
            const std::uint32_t* b = &at[4 * k];  // extended begin, owned begin, owned end, extended end
            mine[std::size_t(d) * n + k] = {b[0], std::uint64_t(b[3] - b[0]), std::uint64_t(b[2] - b[1])};
        }
    }
    const ExchangeCounters c = carry(subs, mine, ranks, placement, false);
    for (int d = 0; d < local; ++d) {
        const int g = first_local + d;
        subs[d]->keep_only_cells(first_cell(ext_begin(g)), first_cell(ext_end(g)));
        subs[d]->accept_received();
        subs[d]->sort_by_cell();
        subs[d]->set_owned_cells(first_cell(slabs.begin(g)), first_cell(slabs.end(g)));
    }
    return c;
}

std::vector<GhostRefresh> SlabExchange::plan_refresh(std::vector<std::unique_ptr<Subdomain>>& subs,
                                                     const SlabDecomposition& slabs, RankGroup& ranks,
                                                     const SubdomainPlacement& placement) {
    const int n = slabs.devices();
    const int first_local = placement.first(ranks.rank()), local = int(subs.size());
    auto ext_begin = [&](int k) { return extended_begin(slabs, k); };
    auto ext_end = [&](int k) { return extended_end(slabs, k); };
    // Per subdomain, cell_start at the edges of: its left ghosts [ghosts_begin, owned_begin),
    // its right ghosts [owned_end, ghosts_end), what its left neighbour holds of it as ghosts
    // [owned_begin, to_left_end) and its right neighbour [to_right_begin, owned_end) (empty at
    // the ends of the domain).
    enum { ghosts_begin, owned_begin, owned_end, ghosts_end, to_left_end, to_right_begin, edges };
    std::vector<std::uint64_t> mine;
    for (int d = 0; d < local; ++d) {
        const int g = first_local + d;
        const std::vector<std::uint32_t> cells = {
            first_cell(ext_begin(g)), first_cell(slabs.begin(g)), first_cell(slabs.end(g)), first_cell(ext_end(g)),
            first_cell(g > 0 ? ext_end(g - 1) : slabs.begin(g)),
            first_cell(g + 1 < n ? ext_begin(g + 1) : slabs.end(g))};
        for (std::uint32_t at : subs[d]->cell_starts(cells)) mine.push_back(at);
    }
    const std::vector<std::uint64_t> at = allgather_values(ranks, mine);
    if (int(at.size()) != n * edges) throw RunError("the ranks disagree on the number of subdomains");
    auto start = [&](int g, int edge) { return at[std::size_t(g) * edges + edge]; };
    std::vector<GhostRefresh> plan;
    auto add = [&](int from, std::uint64_t first, std::uint64_t end, int to, std::uint64_t offset,
                   std::uint64_t ghosts_end) {
        if (end - first != ghosts_end - offset)
            throw RunError("subdomain " + std::to_string(to) + " holds " + std::to_string(ghosts_end - offset) +
                           " ghosts of subdomain " + std::to_string(from) + ", which owns " +
                           std::to_string(end - first) + " particles there: the ghost blocks cannot be refreshed");
        if (end > first) plan.push_back({from, to, first, end - first, offset});
    };
    for (int k = 0; k < n; ++k) {
        if (k > 0) add(k - 1, start(k - 1, to_right_begin), start(k - 1, owned_end), k, start(k, ghosts_begin),
                       start(k, owned_begin));
        if (k + 1 < n) add(k + 1, start(k + 1, owned_begin), start(k + 1, to_left_end), k, start(k, owned_end),
                           start(k, ghosts_end));
    }
    return plan;
}

ExchangeCounters SlabExchange::refresh(std::vector<std::unique_ptr<Subdomain>>& subs,
                                       const std::vector<GhostRefresh>& plan, RankGroup& ranks,
                                       const SubdomainPlacement& placement, bool overlapped) {
    const int first_local = placement.first(ranks.rank());
    auto is_local = [&](int g) { return placement.rank_of(g) == ranks.rank(); };
    ExchangeCounters c;
    std::vector<ParticleTransfer> transfers;  // between this rank's subdomains, in local indices
    // Between ranks, in the plan's order on both sides (every rank holds the whole plan).
    std::vector<StagedPiece> outgoing, incoming;
    std::vector<int> outgoing_rank, incoming_rank;
    for (const GhostRefresh& r : plan) {
        c.ghosts_sent += r.count;
        c.bytes += r.count * refreshed_bytes_per_particle;
        if (is_local(r.from) && is_local(r.to)) {
            transfers.push_back(
                {r.from - first_local, r.to - first_local, r.first, r.count, r.offset, TransferArrays::state});
        } else if (is_local(r.from)) {
            outgoing.push_back({r.from - first_local, r.first, r.count, TransferArrays::state});
            outgoing_rank.push_back(placement.rank_of(r.to));
        } else if (is_local(r.to)) {
            incoming.push_back({r.to - first_local, r.offset, r.count, TransferArrays::state});
            incoming_rank.push_back(placement.rank_of(r.from));
        }
    }
    // The ghosts are written in place: each receiver's whole state is its area.
    std::vector<ParticleSpan> areas;
    for (auto& sub : subs) areas.push_back(sub->state(0, sub->size()));
    overlapped ? transport_->begin_delivery(subs, transfers, areas) : transport_->deliver(subs, transfers, areas);
    if (ranks.size() > 1) send_between_ranks(subs, outgoing, outgoing_rank, incoming, incoming_rank, areas, ranks);
    if (!overlapped) ghosts_refreshed(subs, plan, ranks, placement);
    return c;
}

void SlabExchange::ghosts_refreshed(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<GhostRefresh>& plan,
                                    RankGroup& ranks, const SubdomainPlacement& placement) {
    const int first_local = placement.first(ranks.rank()), local = int(subs.size());
    for (const GhostRefresh& r : plan)
        if (r.to >= first_local && r.to < first_local + local) subs[r.to - first_local]->ghosts_refreshed(r.offset, r.count);
}

ExchangeCounters SlabExchange::carry(std::vector<std::unique_ptr<Subdomain>>& subs,
                                     const std::vector<TransferSize>& mine, RankGroup& ranks,
                                     const SubdomainPlacement& placement, bool overlapped) {
    ExchangeCounters c;
    const int n = placement.subdomains();
    const int me = ranks.rank(), first_local = placement.first(me), local = int(subs.size());
    auto is_local = [&](int g) { return placement.rank_of(g) == ranks.rank(); };
    // Blocks in rank order are subdomains in order: row g of the whole matrix is sizes[g * n, ...).
    const std::vector<TransferSize> sizes = allgather_values(ranks, mine);
    if (int(sizes.size()) != n * n) throw RunError("the ranks disagree on the number of subdomains");

    // Each destination's receive area holds its senders' particles in subdomain order.
    std::vector<std::uint64_t> incoming(n, 0), offset(std::size_t(n) * n, 0);
    for (int g = 0; g < n; ++g)
        for (int k = 0; k < n; ++k) {
            const TransferSize& t = sizes[std::size_t(g) * n + k];
            offset[std::size_t(g) * n + k] = incoming[k];
            incoming[k] += t.count;
            c.particles_migrated += t.owned;
            c.ghosts_sent += t.count - t.owned;
        }
    for (int k = 0; k < n; ++k) c.bytes += incoming[k] * exchanged_bytes_per_particle;

    std::vector<ParticleSpan> areas;
    for (int d = 0; d < local; ++d) areas.push_back(subs[d]->receive_area(incoming[first_local + d]));
    std::vector<ParticleTransfer> transfers;  // between this rank's subdomains, in local indices
    std::vector<StagedPiece> outgoing;        // to other ranks, in packing order: source, then destination
    std::vector<int> outgoing_rank;
    for (int g = first_local; g < first_local + local; ++g)
        for (int k = 0; k < n; ++k) {
            const TransferSize& t = sizes[std::size_t(g) * n + k];
            if (t.count == 0) continue;
            if (is_local(k)) {
                transfers.push_back({g - first_local, k - first_local, t.first, t.count, offset[std::size_t(g) * n + k]});
            } else {
                outgoing.push_back({g - first_local, t.first, t.count});
                outgoing_rank.push_back(placement.rank_of(k));
            }
        }
    overlapped ? transport_->begin_delivery(subs, transfers, areas) : transport_->deliver(subs, transfers, areas);
    if (ranks.size() == 1) return c;
    // What each sender packs, it packs by source subdomain, then destination: read it so.
    std::vector<StagedPiece> incoming_pieces;
    std::vector<int> incoming_rank;
    for (int r = 0; r < ranks.size(); ++r) {
        if (r == me) continue;
        for (int g = placement.first(r); g < placement.first(r) + placement.count(r); ++g)
            for (int k = first_local; k < first_local + local; ++k) {
                const TransferSize& t = sizes[std::size_t(g) * n + k];
                if (t.count == 0) continue;
                incoming_pieces.push_back({k - first_local, offset[std::size_t(g) * n + k], t.count});
                incoming_rank.push_back(r);
            }
    }
    send_between_ranks(subs, outgoing, outgoing_rank, incoming_pieces, incoming_rank, areas, ranks);
    return c;
}

void SlabExchange::send_between_ranks(std::vector<std::unique_ptr<Subdomain>>& subs,
                                      const std::vector<StagedPiece>& outgoing, const std::vector<int>& outgoing_rank,
                                      const std::vector<StagedPiece>& incoming, const std::vector<int>& incoming_rank,
                                      const std::vector<ParticleSpan>& areas, RankGroup& ranks) {
    if (!staging_) throw RunError("an exchange between MPI ranks has no staging for its particles");
    const int me = ranks.rank();
    std::vector<Bytes> sends(ranks.size());
    const std::vector<ParticleSpan> out = staging_->stage_out(subs, outgoing);
    for (std::size_t i = 0; i < outgoing.size(); ++i) pack(sends[outgoing_rank[i]], out[i], outgoing[i].count);
    const std::vector<Bytes> received = ranks.exchange(sends);
    const std::vector<ParticleSpan> in = staging_->stage_in(incoming, areas);
    std::vector<std::size_t> at(ranks.size(), 0);
    for (std::size_t i = 0; i < incoming.size(); ++i) {
        const int r = incoming_rank[i];
        at[r] = unpack(received[r], at[r], in[i], incoming[i].count);
    }
    for (int r = 0; r < ranks.size(); ++r)
        if (r != me && at[r] != received[r].size()) throw RunError("an MPI particle message is longer than its transfer sizes");
    staging_->deliver_in(subs, incoming, areas);
}

ExchangeCounters SlabExchange::begin_boundary_exchange(std::vector<std::unique_ptr<Subdomain>>& subs,
                                                       const SlabDecomposition& now, const SlabDecomposition& next,
                                                       int reach, const std::vector<std::vector<std::uint32_t>>& starts,
                                                       RankGroup& ranks, const SubdomainPlacement& placement) {
    const int n = now.devices();
    const int first_local = placement.first(ranks.rank()), local = int(subs.size());
    std::vector<TransferSize> mine(std::size_t(local) * n);
    for (int d = 0; d < local; ++d) {
        const int g = first_local + d;
        const std::vector<std::uint32_t>& at = starts[d];  // cell_start at slices now.begin(g) .. now.end(g)
        if (int(at.size()) != now.width(g) + 1) throw RunError("the slice starts of a subdomain are out of date");
        for (int k = 0; k < n; ++k) {
            if (k == g) continue;
            const SliceRange r = boundary_send_slices(now, next, g, k, ghost_slices_, reach);
            if (r.empty()) continue;
            const std::uint32_t first = at[r.begin - now.begin(g)], last = at[r.end - now.begin(g)];
            mine[std::size_t(d) * n + k] = {first, std::uint64_t(last - first), 0};
        }
    }
    return carry(subs, mine, ranks, placement, true);
}

std::size_t SlabExchange::settle(Subdomain& sub, int g, const SlabDecomposition& next) {
    const std::uint32_t ext_begin = first_cell(extended_begin(next, g));
    const std::uint32_t ext_end = first_cell(extended_end(next, g));
    const std::uint32_t owned_begin = first_cell(next.begin(g)), owned_end = first_cell(next.end(g));
    const ReceivedCount c = sub.accept_received_in(ext_begin, ext_end, owned_begin, owned_end);
    sub.sort_by_cell();
    sub.keep_only_cells(ext_begin, ext_end);  // what went beyond it is the neighbours' now
    sub.set_owned_cells(owned_begin, owned_end);
    return c.owned;
}

}  // namespace sph
