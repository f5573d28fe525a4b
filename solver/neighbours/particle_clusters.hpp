#pragma once
// Cluster pair lists (GROMACS' NBNXM in miniature, issue 25): the particles of a subdomain, in
// the sorted (cell, id) order, form clusters of cluster_size consecutive particles, cluster k =
// [first + 8k, min(first + 8k + 8, end)). Each rebuild gives every cluster its axis-aligned
// bounding box, and each cluster a list of the clusters whose box comes closer to its own than
// the list's reach (support + skin). Any pair (i, j) closer than the reach then lies in clusters
// that list each other, since two boxes are no farther apart than any two of their members. A
// list holds one 4-byte entry per listed cluster of 8 particles, where a per-particle Verlet
// list holds one per neighbour, and a build tests boxes, not particles.
//
// Open grids only: a box in absolute coordinates has no image across a periodic face (the
// backends refuse periodic grids with this layout).
#include <cstdint>

#include "core/particle.hpp"
#include "neighbours/grid.hpp"

namespace sph {

constexpr std::uint32_t cluster_size = 8;

// A cluster's bounding box in coordinates from the grid's low corner (cell * cell size +
// offset). lo.w is 1 where the cluster holds a fluid particle, 0 where it holds walls only: two
// wall-only clusters have no pair that does anything (walls gather from fluid only), so neither
// lists the other. A cluster with no particle inside the domain has lo > hi and lists nothing.
struct alignas(16) ClusterBox {
    real4 lo, hi;
    SPH_HD bool has_fluid() const { return lo.w > real(0.5); }
};

// How many clusters cover particles [first, end).
SPH_HD std::uint32_t cluster_count(std::uint32_t first, std::uint32_t end) {
    return end > first ? (end - first + cluster_size - 1) / cluster_size : 0;
}

// The box of cluster k of [first, end): its particles' positions against their cells (pos) and
// their cells (cell, linear indices of the last sort). Particles outside the domain (cell past
// the grid) are left out.
SPH_HD ClusterBox cluster_box(std::uint32_t k, std::uint32_t first, std::uint32_t end, const real4* pos,
                              const real4* velrho, const std::uint32_t* cell, const GridView& g) {
    const real big = real(1e30);
    ClusterBox b{{big, big, big, 0}, {-big, -big, -big, 0}};
    const std::uint32_t j0 = first + k * cluster_size;
    const std::uint32_t j1 = end - j0 < cluster_size ? end : j0 + cluster_size;
    const std::uint32_t outside = g.out_of_domain();
    for (std::uint32_t j = j0; j < j1; ++j) {
        const std::uint32_t c = cell[j];
        if (c >= outside) continue;
        const int3v cc = g.decode(c);
        const real4 p = pos[j];
        const real x = real(cc.x) * g.cell_size.x + p.x, y = real(cc.y) * g.cell_size.y + p.y,
                   z = real(cc.z) * g.cell_size.z + p.z;
        b.lo.x = x < b.lo.x ? x : b.lo.x;
        b.lo.y = y < b.lo.y ? y : b.lo.y;
        b.lo.z = z < b.lo.z ? z : b.lo.z;
        b.hi.x = x > b.hi.x ? x : b.hi.x;
        b.hi.y = y > b.hi.y ? y : b.hi.y;
        b.hi.z = z > b.hi.z ? z : b.hi.z;
        if (!is_boundary(velrho[j])) b.lo.w = 1;
    }
    return b;
}

// The squared distance between two boxes (0 where they overlap).
SPH_HD real box_distance2(const ClusterBox& a, const ClusterBox& b) {
    const auto gap = [](real lo_a, real hi_a, real lo_b, real hi_b) {
        const real d = lo_b - hi_a > lo_a - hi_b ? lo_b - hi_a : lo_a - hi_b;
        return d > 0 ? d : real(0);
    };
    const real dx = gap(a.lo.x, a.hi.x, b.lo.x, b.hi.x), dy = gap(a.lo.y, a.hi.y, b.lo.y, b.hi.y),
               dz = gap(a.lo.z, a.hi.z, b.lo.z, b.hi.z);
    return dx * dx + dy * dy + dz * dz;
}

// The cells along one axis that hold every particle within `reach` of [lo, hi], clamped to the
// grid: a particle's cell is its coordinate over the cell size rounded down, up to rounding,
// which the margin of a thousandth of a cell covers.
SPH_HD void cells_within(real lo, real hi, real reach, real cs, int n, int& c0, int& c1) {
    const real margin = real(1e-3);
    const real a = floor_r((lo - reach) / cs - margin), b = floor_r((hi + reach) / cs + margin);
    c0 = a < 0 ? 0 : (a > real(n - 1) ? n : int(a));
    c1 = b < 0 ? -1 : (b > real(n - 1) ? n - 1 : int(b));
}

// Work counters of one cluster's build: the clusters whose box was tested, those listed.
struct ClusterBuildWork {
    std::uint32_t tested = 0, listed = 0;
};

// Builds cluster c's list: every cluster (itself included) whose box lies within `reach` of
// c's, found through the cells around c's box grown by the reach: a column's z-run of cells is
// one particle range, so one range of clusters. Columns come in ascending cell order, so their
// particle ranges and cluster ranges ascend, and a cluster shared by two ranges comes at the end
// of one and the start of the next: the list holds each cluster once, in ascending order.
// Entries at column k of c: index[k * stride + c]. Returns the true count; entries past
// `capacity` are not written (the caller grows and builds again).
SPH_HD ClusterBuildWork build_cluster_list(std::uint32_t c, const ClusterBox* boxes, std::uint32_t first,
                                           std::uint32_t end, const std::uint32_t* cell_start, const GridView& g,
                                           real reach, std::uint32_t* index, std::uint32_t stride,
                                           std::uint32_t capacity) {
    ClusterBuildWork w;
    const ClusterBox bc = boxes[c];
    if (bc.lo.x > bc.hi.x) return w;  // no particle inside the domain
    const real reach2 = reach * reach;
    int x0, x1, y0, y1, z0, z1;
    cells_within(bc.lo.x, bc.hi.x, reach, g.cell_size.x, g.nx, x0, x1);
    cells_within(bc.lo.y, bc.hi.y, reach, g.cell_size.y, g.ny, y0, y1);
    cells_within(bc.lo.z, bc.hi.z, reach, g.cell_size.z, g.nz, z0, z1);
    if (z0 > z1) return w;
    const bool fluid_c = bc.has_fluid();
    std::uint32_t next = 0;  // clusters below it were tested already
    for (int x = x0; x <= x1; ++x)
        for (int y = y0; y <= y1; ++y) {
            const std::uint32_t column = g.encode(x, y, 0);
            std::uint32_t b = cell_start[column + std::uint32_t(z0)], e = cell_start[column + std::uint32_t(z1) + 1];
            b = b < first ? first : b;
            e = e > end ? end : e;
            if (b >= e) continue;
            std::uint32_t k = (b - first) / cluster_size;
            const std::uint32_t k_end = (e - 1 - first) / cluster_size + 1;
            k = k < next ? next : k;
            for (; k < k_end; ++k) {
                const ClusterBox bk = boxes[k];
                ++w.tested;
                if (!fluid_c && !bk.has_fluid()) continue;
                if (box_distance2(bc, bk) >= reach2) continue;
                if (w.listed < capacity) index[std::size_t(w.listed) * stride + c] = k;
                ++w.listed;
            }
            next = k_end > next ? k_end : next;
        }
    return w;
}

}  // namespace sph
