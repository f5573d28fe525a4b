#include "multi/slab_exchange.hpp"

#include <algorithm>

namespace sph {
namespace {

void append_particle(ParticleArrays& to, const ParticleArrays& from, std::size_t k, std::uint32_t id) {
    to.pos.push_back(from.pos[k]);
    to.velrho.push_back(from.velrho[k]);
    to.cell.push_back(from.cell[k]);
    to.id.push_back(id);
}

}  // namespace

ExchangeCounters SlabExchange::migrate(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& before,
                                       const SlabDecomposition& slabs) {
    ExchangeCounters c;
    const int n = int(subs.size());
    std::vector<ParticleArrays> inbox(n);
    const std::uint32_t all_cells = grid_.cell_count();
    for (int d = 0; d < n; ++d) {
        // Only the slices d owned before and still owns hold nothing but its own particles;
        // everything else (stale ghosts, drifted particles, handed-over slices) is sorted out.
        const int keep_lo = std::max(before.begin(d), slabs.begin(d));
        const int keep_hi = std::max(keep_lo, std::min(before.end(d), slabs.end(d)));
        const std::uint32_t lo = first_cell(keep_lo), hi = first_cell(keep_hi);
        for (const auto& [a, b] : {std::pair{0u, lo}, std::pair{hi, all_cells}}) {
            if (a >= b) continue;
            const ParticleArrays out = subs[d]->copy_cells(a, b);
            for (std::size_t k = 0; k < out.size(); ++k) {
                if (is_ghost_id(out.id[k])) continue;  // stale ghost: its owner sends a fresh one
                const int owner = slabs.owner_of(int(out.cell[k] / slice_cells()));
                append_particle(inbox[owner], out, k, out.id[k]);
                if (owner != d) ++c.particles_migrated;
            }
        }
        subs[d]->keep_only_cells(lo, hi);
    }
    for (int d = 0; d < n; ++d) {
        c.bytes += inbox[d].size() * exchanged_bytes_per_particle;
        subs[d]->append(inbox[d]);
    }
    return c;
}

ExchangeCounters SlabExchange::refresh_ghosts(std::vector<std::unique_ptr<Subdomain>>& subs,
                                              const SlabDecomposition& slabs) {
    ExchangeCounters c;
    const int n = int(subs.size());
    std::vector<ParticleArrays> inbox(n);
    for (int d = 0; d < n; ++d) {
        // What each other subdomain k reads from d: d's slices within ghost_slices of k's slab.
        for (int k = 0; k < n; ++k) {
            if (k == d) continue;
            const int lo = std::max(slabs.begin(d), slabs.begin(k) - ghost_slices_);
            const int hi = std::min(slabs.end(d), slabs.end(k) + ghost_slices_);
            if (lo >= hi) continue;
            const ParticleArrays g = subs[d]->copy_cells(first_cell(lo), first_cell(hi));
            for (std::size_t i = 0; i < g.size(); ++i) append_particle(inbox[k], g, i, g.id[i] | ghost_id_flag);
            c.ghosts_sent += g.size();
        }
    }
    for (int d = 0; d < n; ++d) {
        c.bytes += inbox[d].size() * exchanged_bytes_per_particle;
        subs[d]->append(inbox[d]);
        subs[d]->sort_by_cell();
        subs[d]->set_owned_cells(first_cell(slabs.begin(d)), first_cell(slabs.end(d)));
    }
    return c;
}

}  // namespace sph
