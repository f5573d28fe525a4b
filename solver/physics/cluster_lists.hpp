#pragma once
// Per-particle Verlet lists built from cluster lists (neighbours/particle_clusters.hpp; change
// 15 of docs/force-loop-notes.md), written once for both backends: the host's build is the
// reference the GPU's kernel (cuda_cluster_lists.cu) is tested against.
//
// Each rebuild cuts the sorted particles into clusters of at most 8 along the columns and lists,
// per cluster, the clusters whose boxes lie within the reach. Particle i's candidates are then
// the particles of the clusters its cluster lists; it keeps those within the reach, as
// build_particle_list does from its stencil. On an open grid both meet their candidates in
// ascending index order, so both write the same entries in the same order and the listed loop
// sums the same pairs in the same order either way. A cluster list is built from boxes, not
// particles, and its candidates are shared by the 8 particles of a cluster: the GPU's 8 lanes
// of a cluster load them once.
#include "neighbours/particle_clusters.hpp"
#include "physics/interaction.hpp"

namespace sph {

// Cluster lists: cluster c's k-th listed cluster at index[k * stride + c] (a column per list
// position, so that consecutive clusters read one column coalesced), count[c] of them; cluster k
// holds particles [cluster_begin[k], cluster_begin[k + 1]) and particle i is in cluster_of[i]
// (particles [0, end) are in clusters: those inside the domain at the rebuild).
struct ClusterList {
    const std::uint32_t* index;
    const std::uint32_t* count;
    std::uint32_t stride;  // the cluster count
    const std::uint32_t* cluster_of;
    const std::uint32_t* cluster_begin;
    std::uint32_t end;
};

// Work counters of particle i's candidates: every particle of every listed cluster but itself,
// and those inside the support (neighbours).
SPH_HD SearchWork particle_cluster_work(std::uint32_t i, const ForceInputs& in, const ClusterList& list,
                                        const PhysicsParams& p) {
    SearchWork w;
    const int3v ci = in.grid.decode(in.cell[i]);
    const real4 pos_i = in.pos[i];
    const std::uint32_t c = list.cluster_of[i];
    w.ranges = list.count[c];
    for (std::uint32_t k = 0; k < list.count[c]; ++k) {
        const std::uint32_t cj = list.index[std::size_t(k) * list.stride + c];
        const std::uint32_t j0 = list.cluster_begin[cj], j1 = list.cluster_begin[cj + 1];
        for (std::uint32_t j = j0; j < j1; ++j) {
            if (j == i) continue;
            const int3v cj = in.grid.decode(in.cell[j]);
            const real3 rij = separation(pos_i, in.pos[j], cj.x - ci.x, cj.y - ci.y, cj.z - ci.z, in.grid.cell_size);
            const real r2 = dot(rij, rij);
            ++w.candidates;
            if (r2 < p.support2 && r2 > real(1e-18) * p.support2) ++w.neighbours;
        }
    }
    return w;
}

// Candidate j of particle i (cell ci, position pos_i) in cell cj: whether the list keeps it, and
// its entry. A wall keeps fluid only where the inputs tell walls apart by cell (fluid_begin),
// as the stencil's build visits only the cells' fluid then.
template <bool CellOffsets>
SPH_HD bool cluster_candidate_entry(std::uint32_t i, std::uint32_t j, const real4& pos_i, const int3v& ci,
                                    const real4& pos_j, const int3v& cj, bool walls_out, const ForceInputs& in,
                                    real reach2, std::uint32_t& entry) {
    if (j == i) return false;
    const int dx = cj.x - ci.x, dy = cj.y - ci.y, dz = cj.z - ci.z;
    const real3 rij = separation(pos_i, pos_j, dx, dy, dz, in.grid.cell_size);
    if (dot(rij, rij) >= reach2) return false;
    if (walls_out && is_boundary(in.velrho[j])) return false;
    entry = CellOffsets ? ListEntry::encode(j, dx, dy, dz) : j;
    return true;
}

// Whether particle i's list keeps walls out (see cluster_candidate_entry).
SPH_HD bool list_keeps_walls_out(std::uint32_t i, const ForceInputs& in) {
    return in.fluid_begin != nullptr && is_boundary(in.velrho[i]);
}

// Particle i's list from its cluster's (the host's build, the GPU's reference): entries at
// index[k * stride + i]; returns the true count, entries past capacity not written.
template <bool CellOffsets>
SPH_HD std::uint32_t build_particle_list_from_clusters(std::uint32_t i, const ForceInputs& in, const ClusterList& list,
                                                       real reach2, std::uint32_t* index, std::uint32_t stride,
                                                       std::uint32_t capacity) {
    const real4 pos_i = in.pos[i];
    const int3v ci = in.grid.decode(in.cell[i]);
    const bool walls_out = list_keeps_walls_out(i, in);
    const std::uint32_t c = list.cluster_of[i];
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < list.count[c]; ++k) {
        const std::uint32_t cj = list.index[std::size_t(k) * list.stride + c];
        for (std::uint32_t j = list.cluster_begin[cj]; j < list.cluster_begin[cj + 1]; ++j) {
            std::uint32_t entry;
            if (!cluster_candidate_entry<CellOffsets>(i, j, pos_i, ci, in.pos[j], in.grid.decode(in.cell[j]), walls_out,
                                                      in, reach2, entry))
                continue;
            if (n < capacity) index[std::size_t(n) * stride + i] = entry;
            ++n;
        }
    }
    return n;
}

// The reach of the cluster lists a per-particle build reads, for lists of `reach`: a box's
// corners are absolute coordinates (cell x cell size + offset) where a pair's separation is
// formed from cell-relative offsets, and the two round differently, by a few units in the last
// place of the grid's extent. A margin of 16 such units (and 1e-5 of the reach) covers that: a
// few more candidates, never a pair lost.
SPH_HD real cluster_reach_for_lists(real reach, const GridView& g) {
    const real ulp = sizeof(real) == 4 ? real(1.2e-7) : real(2.3e-16);
    const real ex = real(g.nx) * g.cell_size.x, ey = real(g.ny) * g.cell_size.y, ez = real(g.nz) * g.cell_size.z;
    const real extent = ex > ey ? (ex > ez ? ex : ez) : (ey > ez ? ey : ez);
    return reach * real(1.00001) + real(16) * ulp * extent;
}

}  // namespace sph
