#pragma once
#include <algorithm>
// The uniform cell grid of a subdomain. Cells are numbered z fastest, then y, then x (the
// paper's order), so a run of z-neighbouring cells is one contiguous particle range and an
// X slab of cell slices is one contiguous range of the sorted particle arrays.
//
// An axis may be periodic: the grid then spans the domain [lo, hi) along it exactly, cell
// index nx wraps to 0, and a neighbour found across the face is given the unwrapped cell
// offset, so that separations come out right without touching positions.
#include "core/types.hpp"

namespace sph {

// i mod n in [0, n), for any sign of i.
SPH_HD int wrap_index(int i, int n) {
    i %= n;
    return i < 0 ? i + n : i;
}

struct GridView {
    int nx = 1, ny = 1, nz = 1;
    // Per axis: support / n on open axes; on a periodic axis the cells stretch slightly so
    // that a whole number of them spans the period (see make_grid).
    real3 cell_size{1, 1, 1};
    bool periodic_x = false, periodic_y = false, periodic_z = false;

    SPH_HD std::uint32_t cell_count() const { return std::uint32_t(nx) * ny * nz; }
    // The sentinel cell of particles that left the domain: they sort after every real cell.
    SPH_HD std::uint32_t out_of_domain() const { return cell_count(); }
    SPH_HD std::uint32_t encode(int x, int y, int z) const {
        return (std::uint32_t(x) * ny + std::uint32_t(y)) * nz + std::uint32_t(z);
    }
    SPH_HD int3v decode(std::uint32_t c) const {
        const int z = int(c % std::uint32_t(nz));
        const std::uint32_t t = c / std::uint32_t(nz);
        return {int(t / std::uint32_t(ny)), int(t % std::uint32_t(ny)), z};
    }
    SPH_HD bool inside(int x, int y, int z) const {
        return x >= 0 && y >= 0 && z >= 0 && x < nx && y < ny && z < nz;
    }
    SPH_HD bool any_periodic() const { return periodic_x || periodic_y || periodic_z; }
    // Brings a cell coordinate that crossed a periodic face back into the grid; coordinates
    // on open axes are left as they are (inside() then decides).
    SPH_HD int3v wrap_periodic(int3v c) const {
        if (periodic_x) c.x = wrap_index(c.x, nx);
        if (periodic_y) c.y = wrap_index(c.y, ny);
        if (periodic_z) c.z = wrap_index(c.z, nz);
        return c;
    }
};

// A particle's cell as coordinates, 16 bits each: for loops that read a neighbour's cell at
// every pair (the listed loop), where decoding the linear index costs two integer divisions
// (~30 of an entry's ~170 instructions on an H200). Grids with more than 32767 cells along an
// axis cannot use them (fits_cell_coords). A particle that left the domain gets coordinates
// far outside any grid, so that no separation to it falls inside a support.
struct alignas(8) CellCoords {
    std::int16_t x, y, z, unused;
};
constexpr int cell_coords_limit = 32767;
SPH_HD CellCoords pack_cell_coords(int3v c, bool inside) {
    if (!inside) return {-cell_coords_limit, -cell_coords_limit, -cell_coords_limit, 0};
    return {std::int16_t(c.x), std::int16_t(c.y), std::int16_t(c.z), 0};
}
inline bool fits_cell_coords(const GridView& g) {
    return g.nx <= cell_coords_limit && g.ny <= cell_coords_limit && g.nz <= cell_coords_limit;
}

// What the integration keeps up for the listed loop between list rebuilds (members null:
// nothing). With `build_frame` null, `coords` follow each particle's cell. With it, `coords`
// stay the cells of the last rebuild and build_frame[i] is particle i's position against that
// cell (w: P / rho^2, as in pos): a list whose entries carry the cell offsets of the rebuild
// (ListEntry) then gives each pair's separation without reading j's cell (change 12 of
// docs/force-loop-notes.md).
struct KeptCells {
    CellCoords* coords = nullptr;
    real4* build_frame = nullptr;
};

// Host-side description: the grid plus where it sits in the world (in double precision,
// since absolute positions are only ever formed on the host).
struct Grid {
    GridView view;
    double origin[3] = {0, 0, 0};
    int cells_per_support = 1;  // Smaller Cell's n: cell size = support / n (or a little more, periodic)
};

// Builds the grid that covers [lo, hi] with cells of support / n. Along an axis whose
// periodic[axis] is set, [lo, hi) is the period: it is cut into the largest whole number of
// cells no smaller than support / n (at least one), so the cell size there may grow slightly.
Grid make_grid(const double lo[3], const double hi[3], double support, int cells_per_support,
               const bool periodic[3] = nullptr);

// Whether a stencil of n cells each side finds every pair closer than `reach`: what a
// Verlet list built on this grid needs (reach = support + skin).
inline bool stencil_reaches(const GridView& g, int n, double reach) {
    const double shortest = std::min({double(g.cell_size.x), double(g.cell_size.y), double(g.cell_size.z)});
    return shortest * n >= reach * (1 - 1e-6);
}

}  // namespace sph
