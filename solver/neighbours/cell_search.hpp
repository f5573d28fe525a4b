#pragma once
// Cell-linked-list neighbour search strategies, each a compile-time policy so the inner loop
// is specialised, not branched:
//   CellSearch<1, false>  traditional CLL, 27 cells
//   CellSearch<1, true>   Cell Merging: the 3 z-neighbouring cells of each (x, y) column are
//                         one contiguous particle range, so 9 ranges instead of 27 cells
//   CellSearch<n, merge>  Smaller Cell: cells of support / n, (2n+1)^3 cells or (2n+1)^2 ranges
// visit(j, dx, dy, dz) receives each candidate and the cell offset of its cell relative to
// the particle's own cell (what turns cell-relative offsets into a separation vector).
#include "neighbours/grid.hpp"

namespace sph {

template <int N, bool Merge>
struct CellSearch {
    static constexpr int n = N;
    static constexpr bool merge = Merge;

    // cell_start has cell_count() + 1 entries: cell c holds sorted particles
    // [cell_start[c], cell_start[c + 1]).
    template <class Visit>
    SPH_HD static void visit(const GridView& g, const std::uint32_t* cell_start, const std::uint32_t* cell,
                             int3v c, Visit&& visit) {
        const int z0 = c.z - N < 0 ? 0 : c.z - N;
        const int z1 = c.z + N >= g.nz ? g.nz - 1 : c.z + N;
        for (int dx = -N; dx <= N; ++dx) {
            const int x = c.x + dx;
            if (x < 0 || x >= g.nx) continue;
            for (int dy = -N; dy <= N; ++dy) {
                const int y = c.y + dy;
                if (y < 0 || y >= g.ny) continue;
                const std::uint32_t column = g.encode(x, y, 0);
                if constexpr (Merge) {
                    const std::uint32_t end = cell_start[column + z1 + 1];
                    const int ref = int(column) + c.z;
                    for (std::uint32_t j = cell_start[column + z0]; j < end; ++j) visit(j, dx, dy, int(cell[j]) - ref);
                } else {
                    for (int z = z0; z <= z1; ++z) {
                        const std::uint32_t end = cell_start[column + z + 1];
                        for (std::uint32_t j = cell_start[column + z]; j < end; ++j) visit(j, dx, dy, z - c.z);
                    }
                }
            }
        }
    }
};

struct SearchOptions {
    int cells_per_support = 1;  // Smaller Cell's n, 1 to 4
    bool merge = false;         // Cell Merging
    bool verlet = false;        // stored neighbour lists, built with the cell search above
    double skin = 0.1;          // Verlet skin as a fraction of the support radius
    int rebuild_every = 0;      // > 0: rebuild every k steps; 0: when particles may have moved skin / 2
};

}  // namespace sph
