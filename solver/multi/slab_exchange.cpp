#include "multi/slab_exchange.hpp"

#include <algorithm>

namespace sph {

ExchangeCounters SlabExchange::exchange(std::vector<std::unique_ptr<Subdomain>>& subs, const SlabDecomposition& slabs) {
    ExchangeCounters c;
    const int n = int(subs.size());
    const int slices = slabs.slices();
    auto ext_begin = [&](int k) { return std::max(0, slabs.begin(k) - ghost_slices_); };
    auto ext_end = [&](int k) { return std::min(slices, slabs.end(k) + ghost_slices_); };

    // Where each extended slab (and the owned part inside it) starts and ends in each sorted
    // subdomain: one read of cell_start per subdomain.
    std::vector<ParticleTransfer> transfers;
    std::vector<std::size_t> incoming(n, 0);
    for (int d = 0; d < n; ++d) {
        std::vector<std::uint32_t> cells;
        for (int k = 0; k < n; ++k)
            for (int slice : {ext_begin(k), slabs.begin(k), slabs.end(k), ext_end(k)}) cells.push_back(first_cell(slice));
        const std::vector<std::uint32_t> at = subs[d]->cell_starts(cells);
        for (int k = 0; k < n; ++k) {
            if (k == d) continue;
            const std::uint32_t* b = &at[4 * k];  // extended begin, owned begin, owned end, extended end
            const std::size_t count = b[3] - b[0];
            if (count == 0) continue;
            transfers.push_back({d, k, b[0], count, incoming[k]});
            incoming[k] += count;
            c.particles_migrated += b[2] - b[1];
            c.ghosts_sent += count - (b[2] - b[1]);
        }
    }
    std::vector<ParticleSpan> areas;
    for (int k = 0; k < n; ++k) areas.push_back(subs[k]->receive_area(incoming[k]));
    transport_->deliver(subs, transfers, areas);
    for (int d = 0; d < n; ++d) {
        subs[d]->keep_only_cells(first_cell(ext_begin(d)), first_cell(ext_end(d)));
        subs[d]->accept_received();
        subs[d]->sort_by_cell();
        subs[d]->set_owned_cells(first_cell(slabs.begin(d)), first_cell(slabs.end(d)));
        c.bytes += incoming[d] * exchanged_bytes_per_particle;
    }
    return c;
}

}  // namespace sph
