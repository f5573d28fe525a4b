#pragma once
// Cell-linked-list neighbour search strategies, each a compile-time policy so the inner loop
// is specialised, not branched:
//   CellSearch<1, false>  traditional CLL, 27 cells
//   CellSearch<1, true>   Cell Merging: the 3 z-neighbouring cells of each (x, y) column are
//                         one contiguous particle range, so 9 ranges instead of 27 cells
//   CellSearch<n, merge>  Smaller Cell: cells of support / n, (2n+1)^3 cells or (2n+1)^2 ranges
// visit(j, dx, dy, dz) receives each candidate and the cell offset of its cell relative to
// the particle's own cell (what turns cell-relative offsets into a separation vector).
//
// Periodic axes: a stencil cell past a periodic face is read at its wrapped index but
// reported with the unwrapped offset, so the separation is the one to that image of j. On
// a grid of fewer than 2n+1 cells along a periodic axis the stencil reaches the same cell
// at several offsets: each is a different image of its particles (self-images included),
// which is the periodic sum, so nothing is visited twice at the same separation.
#include "neighbours/grid.hpp"

namespace sph {

template <int N, bool Merge>
struct CellSearch {
    static constexpr int n = N;
    static constexpr bool merge = Merge;

    // f(dx, dy, column) for each (x, y) column of the stencil around cell c that lies in the
    // grid (wrapped across periodic x and y faces), column = the index of its cell z = 0.
    template <class F>
    SPH_HD static void for_each_column(const GridView& g, int3v c, F&& f) {
        for (int dx = -N; dx <= N; ++dx) {
            int x = c.x + dx;
            if (x < 0 || x >= g.nx) {
                if (!g.periodic_x) continue;
                x = wrap_index(x, g.nx);
            }
            for (int dy = -N; dy <= N; ++dy) {
                int y = c.y + dy;
                if (y < 0 || y >= g.ny) {
                    if (!g.periodic_y) continue;
                    y = wrap_index(y, g.ny);
                }
                f(dx, dy, g.encode(x, y, 0));
            }
        }
    }

    // The z offset (cell_j.z - cell_i.z, unwrapped) of the candidates of one particle range:
    // a cell's range has one offset; a merged z-run spans several cells, whose offsets come
    // from each candidate's cell index (one more load per candidate, the price of merging).
    struct RangeZ {
        int dz;   // unmerged: the range's offset
        int ref;  // merged: the offset of candidate j is cell[j] - ref
        SPH_HD int of(const std::uint32_t* cell, std::uint32_t j) const {
            if constexpr (Merge) return int(cell[j]) - ref;
            else return dz;
        }
    };

    // f(begin, end, dx, dy, z) for each particle range of the stencil around cell c, in the
    // order visit() reads them: cell_start has cell_count() + 1 entries, cell c holds sorted
    // particles [cell_start[c], cell_start[c + 1]). Along a periodic z a merged run
    // [cz - N, cz + N] is cut where it crosses the face: each piece lies in one image of the
    // grid (shifted by image * nz cells) and is one contiguous range.
    template <class F>
    SPH_HD static void visit_ranges(const GridView& g, const std::uint32_t* cell_start, int3v c, F&& f) {
        const int z0 = c.z - N < 0 ? 0 : c.z - N;
        const int z1 = c.z + N >= g.nz ? g.nz - 1 : c.z + N;
        for_each_column(g, c, [&](int dx, int dy, std::uint32_t column) {
            if (g.periodic_z) {
                if constexpr (Merge) {
                    for (int u = c.z - N; u <= c.z + N;) {
                        const int w0 = wrap_index(u, g.nz);
                        const int shift = u - w0;  // image * nz
                        const int w1 = c.z + N - shift < g.nz - 1 ? c.z + N - shift : g.nz - 1;
                        f(cell_start[column + w0], cell_start[column + w1 + 1], dx, dy,
                          RangeZ{0, int(column) + c.z - shift});
                        u += w1 - w0 + 1;
                    }
                } else {
                    for (int dz = -N; dz <= N; ++dz) {
                        const std::uint32_t z = column + wrap_index(c.z + dz, g.nz);
                        f(cell_start[z], cell_start[z + 1], dx, dy, RangeZ{dz, 0});
                    }
                }
            } else if constexpr (Merge) {
                f(cell_start[column + z0], cell_start[column + z1 + 1], dx, dy, RangeZ{0, int(column) + c.z});
            } else {
                for (int z = z0; z <= z1; ++z)
                    f(cell_start[column + z], cell_start[column + z + 1], dx, dy, RangeZ{z - c.z, 0});
            }
        });
    }

    // visit(j, dx, dy, dz) for each candidate of the stencil around cell c, range by range.
    template <class Visit>
    SPH_HD static void visit(const GridView& g, const std::uint32_t* cell_start, const std::uint32_t* cell,
                             int3v c, Visit&& visit) {
        visit_ranges(g, cell_start, c, [&](std::uint32_t begin, std::uint32_t end, int dx, int dy, RangeZ z) {
            for (std::uint32_t j = begin; j < end; ++j) visit(j, dx, dy, z.of(cell, j));
        });
    }

    // The fluid part of each stencil cell around c, for a boundary particle (which interacts
    // with fluid only): f(begin, end, dx, dy, dz) per cell, in visit()'s cell order, with
    // [begin, end) = [fluid_begin[cell], cell_start[cell + 1]) (the sort puts each cell's
    // boundary particles first: see fluid_begin) and (dx, dy, dz) the cell's offset from c. Cell
    // by cell whatever Merge says: the fluid of a z-run is not one range. Empty cells are
    // passed too (they cost the caller a compare).
    template <class F>
    SPH_HD static void visit_fluid_cells(const GridView& g, const std::uint32_t* cell_start,
                                         const std::uint32_t* fluid_begin, int3v c, F&& f) {
        const int z0 = c.z - N < 0 ? 0 : c.z - N;
        const int z1 = c.z + N >= g.nz ? g.nz - 1 : c.z + N;
        for_each_column(g, c, [&](int dx, int dy, std::uint32_t column) {
            if (g.periodic_z) {
                for (int dz = -N; dz <= N; ++dz) {
                    const std::uint32_t cz = column + wrap_index(c.z + dz, g.nz);
                    f(fluid_begin[cz], cell_start[cz + 1], dx, dy, dz);
                }
            } else {
                for (int z = z0; z <= z1; ++z) f(fluid_begin[column + z], cell_start[column + z + 1], dx, dy, z - c.z);
            }
        });
    }

    // The ranges of visit_ranges() around cell c, or for a wall particle (fluid_only) the
    // fluid of visit_fluid_cells()' cells, in a sequence that is the same around every cell:
    // each (dx, dy) column of the stencil in order, then (unmerged) each dz, with a range that
    // lies outside the grid (or every range, when !walk) passed empty. The lanes of a GPU warp
    // walk their stencils in step this way. A merged run is passed whole even for a wall
    // particle (its cells' walls are the caller's to skip: a run's fluid is not one range).
    // Not for merged runs across a periodic z face, which come in pieces.
    template <class F>
    SPH_HD static void visit_ranges_in_step(const GridView& g, const std::uint32_t* cell_start,
                                            const std::uint32_t* fluid_begin, int3v c, bool walk, bool fluid_only,
                                            F&& f) {
        for (int dx = -N; dx <= N; ++dx) {
            int x = c.x + dx;
            bool x_ok = walk;
            if (x < 0 || x >= g.nx) {
                if (g.periodic_x) x = wrap_index(x, g.nx);
                else x_ok = false;
            }
            for (int dy = -N; dy <= N; ++dy) {
                int y = c.y + dy;
                bool ok = x_ok;
                if (y < 0 || y >= g.ny) {
                    if (g.periodic_y) y = wrap_index(y, g.ny);
                    else ok = false;
                }
                const std::uint32_t column = ok ? g.encode(x, y, 0) : 0;
                if constexpr (Merge) {
                    const int z0 = c.z - N < 0 ? 0 : c.z - N, z1 = c.z + N >= g.nz ? g.nz - 1 : c.z + N;
                    const std::uint32_t b = ok ? cell_start[column + z0] : 0;
                    const std::uint32_t e = ok ? cell_start[column + z1 + 1] : 0;
                    f(b, e, dx, dy, RangeZ{0, int(column) + c.z});
                } else {
                    for (int dz = -N; dz <= N; ++dz) {
                        int z = c.z + dz;
                        bool z_ok = ok;
                        if (z < 0 || z >= g.nz) {
                            if (g.periodic_z) z = wrap_index(z, g.nz);
                            else z_ok = false;
                        }
                        const std::uint32_t cz = column + std::uint32_t(z);
                        const std::uint32_t b = z_ok ? (fluid_only ? fluid_begin[cz] : cell_start[cz]) : 0;
                        const std::uint32_t e = z_ok ? cell_start[cz + 1] : 0;
                        f(b, e, dx, dy, RangeZ{dz, 0});
                    }
                }
            }
        }
    }

    // How many particle ranges visit() reads around cell c (cells, or merged z-runs).
    SPH_HD static unsigned ranges(const GridView& g, int3v c) {
        unsigned cols = 0, runs = 0;
        for (int dx = -N; dx <= N; ++dx)
            for (int dy = -N; dy <= N; ++dy) {
                const bool x_ok = g.periodic_x || (c.x + dx >= 0 && c.x + dx < g.nx);
                const bool y_ok = g.periodic_y || (c.y + dy >= 0 && c.y + dy < g.ny);
                if (x_ok && y_ok) ++cols;
            }
        if (!g.periodic_z) {
            for (int dz = -N; dz <= N; ++dz)
                if (c.z + dz >= 0 && c.z + dz < g.nz) ++runs;
            return cols * (Merge ? 1 : runs);
        }
        if constexpr (Merge) {
            for (int u = c.z - N; u <= c.z + N;) {  // the pieces of the wrapped run, as above
                const int w0 = wrap_index(u, g.nz);
                const int w1 = c.z + N - (u - w0) < g.nz - 1 ? c.z + N - (u - w0) : g.nz - 1;
                ++runs;
                u += w1 - w0 + 1;
            }
            return cols * runs;
        } else {
            return cols * (2 * N + 1);
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

// The distance the grid's cells must cover: the support, or with Verlet lists support + skin,
// since a list holds while particles close at most the skin (pairs just beyond the support in
// cells outside the stencil would otherwise never be listed).
inline double search_reach(double support, const SearchOptions& s) {
    return support * (s.verlet ? 1 + s.skin : 1.0);
}

}  // namespace sph
