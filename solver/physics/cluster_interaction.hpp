#pragma once
// The force loop over cluster pair lists (neighbours/particle_clusters.hpp), written once for
// both backends: particle i walks the list of its cluster and, in each listed cluster, every
// particle but itself, through the same pair sums as every other loop (PairSums). Between
// rebuilds each pair's separation comes from both particles' cells as the listed loop forms it
// (cell coordinates kept by the integration where the inputs have them, else decoded).
//
// Clusters ascend in the list and particles ascend in a cluster, so particle i meets its
// neighbours in ascending index order: the order a per-particle list built on an open grid
// holds them in (its stencil's columns and z-runs ascend in cell order), so both layouts give
// the same sums on the host.
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

// Particle i's sums over its cluster's list. Choices are the listed loop's (ListedLoopDefaults
// on the host, a GPU's launch policy there): packed_cells, early_loads and whole_loads apply;
// entry_offsets and index_lookahead do not (a cluster entry carries no cell offset). Open grids
// only (the backends refuse periodic ones with this layout).
// HitMasks tests a listed cluster's particles first, one bit each, then runs the pair body over
// the bits: a warp's lanes (4 clusters) meet a neighbour in ~1 of 4 candidates, and candidate by
// candidate the warp runs the body whenever one lane has a neighbour. The same pairs in the same
// order through the same arithmetic: the same sums to the bit (tests/test_cluster_lists.cpp).
template <class Kernel, bool Diffusion, class Choices = ListedLoopDefaults, bool HitMasks = false>
SPH_HD real4 particle_force_cluster_listed(std::uint32_t i, const ForceInputs& in, const ClusterList& list,
                                           const PhysicsParams& p, const Kernel& kernel) {
    static_assert(!Choices::whole_loads || Choices::early_loads, "whole_loads are early loads");
    PairSums<Kernel, Diffusion> sums(i, in, p, kernel);
    const auto cell_of = [&](std::uint32_t k) {
        if constexpr (Choices::packed_cells) {
            const CellCoords c = in.cell_coords[k];
            return int3v{c.x, c.y, c.z};
        } else {
            return in.grid.decode(in.cell[k]);
        }
    };
    const int3v ci = cell_of(i);
    const auto separation_to = [&](std::uint32_t j, const real4& pos_j) {
        const int3v cj = cell_of(j);
        return separation(sums.side.pos, pos_j, cj.x - ci.x, cj.y - ci.y, cj.z - ci.z, in.grid.cell_size);
    };
    const auto add = [&](std::uint32_t j) {
        const real4 pos_j = Choices::whole_loads ? load_whole(in.pos, j) : in.pos[j];
        const real3 rij = separation_to(j, pos_j);
        if constexpr (Choices::whole_loads) sums.add_loaded(j, pos_j, load_whole(in.velrho, j), rij, dot(rij, rij));
        else if constexpr (Choices::early_loads) sums.add_loaded(j, in.velrho[j], rij, dot(rij, rij));
        else sums.add(j, rij, dot(rij, rij));
    };
    const real near2 = real(1e-18) * p.support2;
    const std::uint32_t c = list.cluster_of[i];
    const std::uint32_t n = list.count[c];
    for (std::uint32_t k = 0; k < n; ++k) {
        const std::uint32_t cj = list.index[std::size_t(k) * list.stride + c];
        const std::uint32_t j0 = list.cluster_begin[cj], j1 = list.cluster_begin[cj + 1];
        if constexpr (HitMasks) {
            std::uint32_t hits = 0;
            for (std::uint32_t j = j0; j < j1; ++j) {
                const real3 rij = separation_to(j, in.pos[j]);
                const real r2 = dot(rij, rij);
                if (r2 < p.support2 && r2 > near2 && j != i) hits |= std::uint32_t(1) << (j - j0);
            }
            while (hits != 0) {
                const std::uint32_t j = j0 + std::uint32_t(lowest_set_bit(hits));
                hits &= hits - 1;
                add(j);  // the same separation as the test's
            }
        } else {
            for (std::uint32_t j = j0; j < j1; ++j)
                if (j != i) add(j);
        }
    }
    return sums.result();
}

// Work counters of particle i's walk: the pairs it tests (candidates: every particle of every
// listed cluster but itself) and those inside the support (neighbours), as the walk sees them.
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

}  // namespace sph

namespace sph {

// Per-particle Verlet lists built from cluster lists (list_build = clusters, change 15 of
// docs/force-loop-notes.md): particle i's candidates are the particles of the clusters its
// cluster lists (built at a reach a little longer than the lists', so that no pair inside the
// lists' reach is lost to the boxes' rounding); it keeps those within the reach, as
// build_particle_list does from its stencil. On an open grid both meet the candidates in
// ascending index order, so both write the same entries in the same order.
//
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
