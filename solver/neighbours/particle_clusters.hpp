#pragma once
// Cluster pair lists (GROMACS' NBNXM in miniature, issue 25): the particles of a subdomain, in
// the sorted (cell, id) order, form clusters of at most cluster_size consecutive particles. Each
// rebuild gives every cluster its axis-aligned bounding box, and each cluster a list of the
// clusters whose box comes closer to its own than the list's reach (support + skin). Any pair
// (i, j) closer than the reach then lies in clusters that list each other, since two boxes are no
// farther apart than any two of their members. A list holds one 4-byte entry per listed cluster
// of up to 8 particles, where a per-particle Verlet list holds one per neighbour, and a build
// tests boxes, not particles.
//
// Clusters do not cross a gap: a segment is a run of non-empty cells of one (x, y) column (one
// contiguous particle range, z ascending), and each segment is cut into clusters of 8 from its
// start, the last one shorter. Eight particles straight from the sorted order would put, once
// per column, a cluster across the jump from one column's top to the next one's bottom (or, in a
// wall's row, across the whole tank): its box then spans the water's height or the tank, and on
// DualSPHysics' dam break at rest (1.04M) such clusters listed up to 14,000 clusters; cut along
// segments, the longest list holds 132 and the median 85 (change 14 of docs/force-loop-notes.md).
//
// What a rebuild makes: each column's cluster count (column_cluster_count), their exclusive sum
// over the columns (the first cluster of each column), then per column its clusters' first
// particles and each particle's cluster (fill_column_clusters), each cluster's box (cluster_box)
// and each cluster's list (build_cluster_list). Clusters are numbered in particle order.
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
// lists the other.
struct alignas(16) ClusterBox {
    real4 lo, hi;
    SPH_HD bool has_fluid() const { return lo.w > real(0.5); }
};

// The particles of the grid's column `column` (x * ny + y) lie in cells [column * nz, column * nz
// + nz). f(begin, end) for each of its segments (runs of non-empty cells), z ascending.
template <class F>
SPH_HD void for_each_segment(std::uint32_t column, const std::uint32_t* cell_start, int nz, F&& f) {
    const std::uint32_t c0 = column * std::uint32_t(nz);
    std::uint32_t begin = cell_start[c0];
    for (std::uint32_t z = 0; z < std::uint32_t(nz); ++z) {
        const std::uint32_t b = cell_start[c0 + z], e = cell_start[c0 + z + 1];
        if (b == e) {  // an empty cell ends the segment before it
            if (begin < b) f(begin, b);
            begin = e;
        }
    }
    const std::uint32_t end = cell_start[c0 + std::uint32_t(nz)];
    if (begin < end) f(begin, end);
}

// How many clusters the column's segments make.
SPH_HD std::uint32_t column_cluster_count(std::uint32_t column, const std::uint32_t* cell_start, int nz) {
    std::uint32_t n = 0;
    for_each_segment(column, cell_start, nz,
                     [&](std::uint32_t b, std::uint32_t e) { n += (e - b + cluster_size - 1) / cluster_size; });
    return n;
}

// Writes the column's clusters, numbered from first_cluster: cluster_begin[k] (the first
// particle of cluster k; the clusters after the last column's end at the particles' end, which the
// caller writes at cluster_begin[cluster count]) and cluster_of[i] for each of their particles.
SPH_HD void fill_column_clusters(std::uint32_t column, const std::uint32_t* cell_start, int nz,
                                 std::uint32_t first_cluster, std::uint32_t* cluster_begin, std::uint32_t* cluster_of) {
    std::uint32_t k = first_cluster;
    for_each_segment(column, cell_start, nz, [&](std::uint32_t b, std::uint32_t e) {
        for (std::uint32_t i = b; i < e; i += cluster_size, ++k) {
            cluster_begin[k] = i;
            const std::uint32_t stop = e - i < cluster_size ? e : i + cluster_size;
            for (std::uint32_t j = i; j < stop; ++j) cluster_of[j] = k;
        }
    });
}

// The box of the particles [begin, end) of one cluster: their positions against their cells
// (pos) and their cells (cell, linear indices of the last sort).
SPH_HD ClusterBox cluster_box(std::uint32_t begin, std::uint32_t end, const real4* pos, const real4* velrho,
                              const std::uint32_t* cell, const GridView& g) {
    const real big = real(1e30);
    ClusterBox b{{big, big, big, 0}, {-big, -big, -big, 0}};
    for (std::uint32_t j = begin; j < end; ++j) {
        const int3v cc = g.decode(cell[j]);
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
// one particle range, so one range of clusters (cluster_of its first and last particles).
// Columns come in ascending cell order, so their particle ranges and cluster ranges ascend, and a
// cluster shared by two ranges comes at the end of one and the start of the next: the list holds
// each cluster once, in ascending order. Entries at column k of c: index[k * stride + c]. Returns
// the true count; entries past `capacity` are not written (the caller grows and builds again).
SPH_HD ClusterBuildWork build_cluster_list(std::uint32_t c, const ClusterBox* boxes, const std::uint32_t* cluster_of,
                                           const std::uint32_t* cell_start, const GridView& g, real reach,
                                           std::uint32_t* index, std::uint32_t stride, std::uint32_t capacity) {
    ClusterBuildWork w;
    const ClusterBox bc = boxes[c];
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
            const std::uint32_t b = cell_start[column + std::uint32_t(z0)], e = cell_start[column + std::uint32_t(z1) + 1];
            if (b >= e) continue;
            std::uint32_t k = cluster_of[b];
            const std::uint32_t k_end = cluster_of[e - 1] + 1;
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
