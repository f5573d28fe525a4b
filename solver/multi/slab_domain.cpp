#include "multi/slab_domain.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace sph {
namespace {

std::vector<long long> particles_per_slice(const GridView& grid, const ParticleArrays& all) {
    const std::uint32_t slice_cells = std::uint32_t(grid.ny) * std::uint32_t(grid.nz);
    std::vector<long long> per_slice(grid.nx, 0);
    for (std::uint32_t c : all.cell)
        if (c < grid.out_of_domain()) ++per_slice[c / slice_cells];
    return per_slice;
}

// One slab needs no ghosts, so no minimum width beyond one slice.
SlabDecomposition initial_slabs(const GridView& grid, int subdomains, int ghost_slices, const ParticleArrays& all) {
    if (subdomains < 1)
        throw InputError("the number of subdomains must be at least 1, got " + std::to_string(subdomains));
    if (subdomains == 1) return SlabDecomposition(grid.nx, 1, 1);
    return SlabDecomposition::balanced_by_particles(particles_per_slice(grid, all), subdomains, ghost_slices);
}

}  // namespace

SlabDomain::SlabDomain(const GridView& grid, int subdomains, int ghost_slices, const std::string& balancer,
                       const ParticleArrays& all, RankGroup& ranks, bool overlap)
    : grid_(grid), slice_cells_(std::uint32_t(grid.ny) * std::uint32_t(grid.nz)), ghost_slices_(ghost_slices),
      ranks_(ranks), placement_(std::max(subdomains, 1), ranks.size()),
      slabs_(initial_slabs(grid, subdomains, ghost_slices, all)), exchanged_for_(slabs_), overlap_(overlap) {
    if (split()) balancer_ = make_balancer(balancer);
}

std::vector<ParticleArrays> SlabDomain::local_parts(const ParticleArrays& all) const {
    if (!split()) return {all};
    std::vector<ParticleArrays> parts(local_count());
    const int first = first_local(), last = first + local_count();
    for (std::size_t i = 0; i < all.size(); ++i) {
        const std::uint32_t c = all.cell[i];
        const int d = c < grid_.out_of_domain() ? slabs_.owner_of(int(c / slice_cells_)) : 0;
        if (d < first || d >= last) continue;
        ParticleArrays& p = parts[d - first];
        p.pos.push_back(all.pos[i]);
        p.velrho.push_back(all.velrho[i]);
        p.cell.push_back(c);
        p.id.push_back(all.id[i]);
    }
    return parts;
}

void SlabDomain::connect(std::vector<std::unique_ptr<Subdomain>>& subs, TransportKind kind,
                         const RankTransportChoice& rank_transport) {
    if (!split()) return;
    rank_transport_ = rank_transport;
    for (int d = 0; d < int(subs.size()); ++d) {
        const int g = first_local() + d;
        subs[d]->set_owned_cells(first_cell(slabs_.begin(g)), first_cell(slabs_.end(g)));
    }
    exchange_ = std::make_unique<SlabExchange>(grid_, ghost_slices_, make_transport(kind, subs, transport_note_),
                                               make_rank_staging(rank_transport.kind, subs));
}

void SlabDomain::drop_ghosts(int local, Subdomain& sub) const {
    if (!split()) return;
    const int g = first_local() + local;
    sub.keep_only_cells(first_cell(exchanged_for_.begin(g)), first_cell(exchanged_for_.end(g)));
}

int SlabDomain::rebalance(std::vector<std::unique_ptr<Subdomain>>& subs, long step,
                          const std::vector<double>& update_times) {
    if (!split() || int(update_times.size()) != subdomains()) return 0;  // no timed step yet
    read_slices(subs);  // the times were measured on these slabs: no scaling
    return decide_balance(step, update_times, {});
}

void SlabDomain::read_slices(std::vector<std::unique_ptr<Subdomain>>& subs) {
    if (!split()) return;
    starts_.resize(subs.size());
    for (int d = 0; d < int(subs.size()); ++d) {
        const int g = first_local() + d;
        std::vector<std::uint32_t> cells;
        for (int x = slabs_.begin(g); x <= slabs_.end(g); ++x) cells.push_back(first_cell(x));
        starts_[d] = subs[d]->cell_starts(cells);
    }
}

// Each rank counts the slices of its own slabs; the sum over ranks is exact (one nonzero
// contribution per slice).
std::vector<long long> SlabDomain::per_slice_counts() const {
    std::vector<long long> mine(slabs_.slices(), 0);
    for (int d = 0; d < int(starts_.size()); ++d) {
        const int g = first_local() + d;
        for (int x = slabs_.begin(g); x < slabs_.end(g); ++x)
            mine[x] = starts_[d][x - slabs_.begin(g) + 1] - starts_[d][x - slabs_.begin(g)];
    }
    if (ranks_.size() == 1) return mine;
    const std::vector<long long> all = allgather_values(ranks_, mine);
    std::vector<long long> per_slice(mine.size(), 0);
    for (std::size_t i = 0; i < all.size(); ++i) per_slice[i % per_slice.size()] += all[i];
    return per_slice;
}

int SlabDomain::decide_balance(long step, const std::vector<double>& update_times,
                               const std::vector<std::size_t>& measured_particles) {
    if (!split() || int(update_times.size()) != subdomains()) return 0;  // no timed step yet
    const std::vector<long long> per_slice = per_slice_counts();
    std::vector<double> times = update_times;
    if (int(measured_particles.size()) == subdomains())
        for (int d = 0; d < subdomains(); ++d)
            if (measured_particles[d] > 0)
                times[d] *= double(slabs_.particles(d, per_slice)) / double(measured_particles[d]);
    const int moved = slabs_.apply_moves(balancer_->decide(slabs_, BalanceInput{times, per_slice, step}));
    if (moved > 0) refresh_planned_ = false;  // the ghost blocks change holders
    return moved;
}

void SlabDomain::set_reach(double max_displacement) {
    // A particle at offset o in [0, cs) of its cell that moves by at most D crosses at most
    // ceil(D / cs) slice faces; the margin covers the rounding of the update's float offsets.
    const double slices = max_displacement / double(grid_.cell_size.x);
    reach_ = slices >= 0 && slices < slabs_.slices() ? std::max(1, int(std::ceil(slices * 1.001 + 1e-3)))
                                                     : slabs_.slices();  // also NaN: everything may move
}

std::array<SlabDomain::CellRange, 3> SlabDomain::update_order(int local) const {
    const BoundaryArea a = boundary_area(exchanged_for_, slabs_, first_local() + local, ghost_slices_, reach_);
    return {CellRange{first_cell(a.begin), first_cell(a.left_end)}, CellRange{first_cell(a.right_begin), first_cell(a.end)},
            CellRange{first_cell(a.left_end), first_cell(a.right_begin)}};
}

void SlabDomain::begin_exchange(std::vector<std::unique_ptr<Subdomain>>& subs) {
    sent_ = exchange_->begin_boundary_exchange(subs, exchanged_for_, slabs_, reach_, starts_, ranks_, placement_);
    in_flight_ = true;
    migrated_ = 0;
}

void SlabDomain::settle(int local, Subdomain& sub) {
    migrated_ += exchange_->settle(sub, first_local() + local, slabs_);
}

ExchangeCounters SlabDomain::settled() {
    ExchangeCounters c = sent_;
    c.particles_migrated = 0;
    for (unsigned long long m : allgather_values(ranks_, std::vector<unsigned long long>{migrated_})) c.particles_migrated += m;
    c.ghosts_sent = c.ghosts_sent >= c.particles_migrated ? c.ghosts_sent - c.particles_migrated : 0;
    exchanged_for_ = slabs_;
    in_flight_ = false;
    refresh_planned_ = false;
    return c;
}

ExchangeCounters SlabDomain::exchange(std::vector<std::unique_ptr<Subdomain>>& subs) {
    if (!split()) return {};
    const ExchangeCounters c = exchange_->exchange(subs, slabs_, ranks_, placement_);
    exchanged_for_ = slabs_;
    refresh_planned_ = false;
    return c;
}

void SlabDomain::plan_refresh(std::vector<std::unique_ptr<Subdomain>>& subs) {
    if (!split()) return;
    refresh_plan_ = exchange_->plan_refresh(subs, exchanged_for_, ranks_, placement_);
    refresh_planned_ = true;
}

ExchangeCounters SlabDomain::refresh(std::vector<std::unique_ptr<Subdomain>>& subs) {
    return refresh_ghosts(subs, false);
}

ExchangeCounters SlabDomain::begin_refresh(std::vector<std::unique_ptr<Subdomain>>& subs) {
    return refresh_ghosts(subs, true);
}

ExchangeCounters SlabDomain::refresh_ghosts(std::vector<std::unique_ptr<Subdomain>>& subs, bool overlapped) {
    if (!split()) return {};
    // A move since the plan changed owners: only a whole exchange carries it.
    if (!refresh_planned_) throw RunError("a ghost refresh needs a plan made right after the last exchange, with no move since");
    refresh_in_flight_ = overlapped;  // finish_exchange then tells the receivers
    return exchange_->refresh(subs, refresh_plan_, ranks_, placement_, overlapped);
}

void SlabDomain::finish_exchange(std::vector<std::unique_ptr<Subdomain>>& subs) {
    exchange_->finish_boundary_exchange(subs);
    if (!refresh_in_flight_) return;
    refresh_in_flight_ = false;
    exchange_->ghosts_refreshed(subs, refresh_plan_, ranks_, placement_);
}

}  // namespace sph
