#include "multi/slab_domain.hpp"

#include <algorithm>

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
                       const ParticleArrays& all, RankGroup& ranks)
    : grid_(grid), slice_cells_(std::uint32_t(grid.ny) * std::uint32_t(grid.nz)), ghost_slices_(ghost_slices),
      ranks_(ranks), placement_(std::max(subdomains, 1), ranks.size()),
      slabs_(initial_slabs(grid, subdomains, ghost_slices, all)), exchanged_for_(slabs_) {
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

void SlabDomain::connect(std::vector<std::unique_ptr<Subdomain>>& subs, TransportKind kind) {
    if (!split()) return;
    for (int d = 0; d < int(subs.size()); ++d) {
        const int g = first_local() + d;
        subs[d]->set_owned_cells(first_cell(slabs_.begin(g)), first_cell(slabs_.end(g)));
    }
    exchange_ = std::make_unique<SlabExchange>(grid_, ghost_slices_, make_transport(kind, subs, transport_note_));
}

void SlabDomain::drop_ghosts(int local, Subdomain& sub) const {
    if (!split()) return;
    const int g = first_local() + local;
    sub.keep_only_cells(first_cell(exchanged_for_.begin(g)), first_cell(exchanged_for_.end(g)));
}

int SlabDomain::rebalance(std::vector<std::unique_ptr<Subdomain>>& subs, long step,
                          const std::vector<double>& update_times) {
    if (!split() || int(update_times.size()) != subdomains()) return 0;  // no timed step yet
    // Each rank counts the slices of its own slabs; the sum over ranks is exact (one nonzero
    // contribution per slice).
    std::vector<long long> mine(slabs_.slices(), 0);
    for (int d = 0; d < int(subs.size()); ++d) {
        const int g = first_local() + d;
        std::vector<std::uint32_t> cells;
        for (int x = slabs_.begin(g); x <= slabs_.end(g); ++x) cells.push_back(first_cell(x));
        const std::vector<std::uint32_t> starts = subs[d]->cell_starts(cells);
        for (int x = slabs_.begin(g); x < slabs_.end(g); ++x)
            mine[x] = starts[x - slabs_.begin(g) + 1] - starts[x - slabs_.begin(g)];
    }
    std::vector<long long> per_slice = mine;
    if (ranks_.size() > 1) {
        const std::vector<long long> all = allgather_values(ranks_, mine);
        std::fill(per_slice.begin(), per_slice.end(), 0);
        for (std::size_t i = 0; i < all.size(); ++i) per_slice[i % per_slice.size()] += all[i];
    }
    return slabs_.apply_moves(balancer_->decide(slabs_, BalanceInput{update_times, per_slice, step}));
}

ExchangeCounters SlabDomain::exchange(std::vector<std::unique_ptr<Subdomain>>& subs) {
    if (!split()) return {};
    const ExchangeCounters c = exchange_->exchange(subs, slabs_, ranks_, placement_);
    exchanged_for_ = slabs_;
    return c;
}

}  // namespace sph
