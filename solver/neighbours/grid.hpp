#pragma once
// The uniform cell grid of a subdomain. Cells are numbered z fastest, then y, then x (the
// paper's order), so a run of z-neighbouring cells is one contiguous particle range and an
// X slab of cell slices is one contiguous range of the sorted particle arrays.
#include "core/types.hpp"

namespace sph {

struct GridView {
    int nx = 1, ny = 1, nz = 1;
    real cell_size = 1;

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
};

// Host-side description: the grid plus where it sits in the world (in double precision,
// since absolute positions are only ever formed on the host).
struct Grid {
    GridView view;
    double origin[3] = {0, 0, 0};
    int cells_per_support = 1;  // Smaller Cell's n: cell size = support / n
};

// Builds the grid that covers [lo, hi] with cells of support / n.
Grid make_grid(const double lo[3], const double hi[3], double support, int cells_per_support);

}  // namespace sph
