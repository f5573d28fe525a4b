#pragma once
// The Verlet list build with one stencil per warp (build_lists_warp_stencil_kernel).
//
// Why: the lane-by-lane builds (build_lists_kernel, build_lists_in_step_kernel) have each lane
// walk its own cell's stencil, so every candidate load of a warp gathers 32 different
// particles over ~9 cache lines, as the listed loop does; on a flowing dam break the rebuild
// (sort and build) cost three to four listed steps. A warp's 32 lanes are 32 consecutive
// particles in cell order, mostly in a few z-neighbouring cells of one (x, y) column, so they
// can share one stencil: the union of their cells' stencils is the same columns with a z-run
// a few cells longer. The warp walks it once, every lane reads the same candidate (one
// address: one L1 wavefront for the warp) and tests it against its own particle. A lane keeps
// a candidate only where its own stencil holds it (|dz| <= n) and it lies within reach, so
// each lane lists exactly the particles the lane-by-lane builds list, in the same order:
// columns in for_each_column's order, particles in cell order within a column's z-run, which
// is ascending j on an open grid (the ListedLoopChoices and CUDA tests hold the lists to that).
// Lanes of other columns (a warp that straddles two columns) walk their own union after.
//
// Open grids only: across a periodic face a column's run comes in pieces and the offsets
// need the images (the driver keeps the in-step build there).
#include <cstdint>

#include "backend/cuda_pair_queue.cuh"
#include "physics/interaction.hpp"

namespace sph::gpu {

template <class Search, bool CellOffsets, int BlockSize, std::uint32_t StageRows>
__global__ void __launch_bounds__(BlockSize)
    build_lists_warp_stencil_kernel(ForceInputs in, real reach2, std::uint32_t* index, std::uint32_t* count,
                                    std::uint32_t stride, std::uint32_t capacity, const std::uint32_t* range_begin,
                                    const std::uint32_t* range_end) {
    constexpr int N = Search::n;
    // Each lane's newest entries, stored by whole rows as in build_lists_in_step_kernel.
    __shared__ std::uint32_t stage[BlockSize / 32][StageRows][32];
    // 32 candidates at a time: loaded by the warp's lanes together (coalesced, one memory
    // latency for 32), then read by every lane from shared memory at one address.
    __shared__ real4 batch_pos[BlockSize / 32][32];
    __shared__ std::uint32_t batch_cell[BlockSize / 32][32];
    const std::uint32_t end = *range_end;
    const std::uint32_t i = *range_begin + blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t lane = threadIdx.x % 32, first = i - lane;
    if (first >= end) return;  // the whole warp is past the end
    const bool valid = i < end;
    const std::uint32_t me = valid ? i : end - 1;
    auto& ring = stage[threadIdx.x / 32];
    auto& cand_pos = batch_pos[threadIdx.x / 32];
    auto& cand_cell = batch_cell[threadIdx.x / 32];
    const real4 pos_i = in.pos[me];
    const bool fluid_i = !is_boundary(in.velrho[me]);
    const GridView& g = in.grid;
    const real3 cs = g.cell_size;
    const int3v c = g.decode(in.cell[me]);
    std::uint32_t n = 0;       // this lane's entries so far
    std::uint32_t stored = 0;  // rows [0, stored) of the walking lanes are in index (warp-uniform)
    // Walls list a few fluid entries where fluid lanes list ~200: they store their own from the
    // start and do not hold back the warp's filled rows (as in build_lists_in_step_kernel).
    std::uint32_t direct = valid && fluid_i ? 0xffffffffu : 0u;
    const bool staging = direct != 0;
    bool walks = false;  // this lane's column is the one the warp walks now
    const auto store_rows = [&](std::uint32_t up_to) {
        const std::uint32_t mine = min(min(n, direct), capacity);
        for (std::uint32_t r = stored; r < up_to; ++r)
            if (walks && r < mine) index[std::size_t(r) * stride + i] = ring[r % StageRows][lane];
        stored = up_to;
    };
    std::uint32_t pending = __ballot_sync(full_warp, valid);  // lanes whose column is still to walk
    while (pending != 0) {
        const int leader = __ffs(int(pending)) - 1;
        const int cx = __shfl_sync(full_warp, c.x, leader), cy = __shfl_sync(full_warp, c.y, leader);
        walks = ((pending >> lane) & 1u) != 0 && c.x == cx && c.y == cy;
        pending &= ~__ballot_sync(full_warp, walks);
        // Lanes of an earlier column flushed every row; this column's start at row 0.
        stored = 0;
        const int zlo = __reduce_min_sync(full_warp, walks ? c.z : 0x7fffffff);
        const int zhi = __reduce_max_sync(full_warp, walks ? c.z : -1);
        const bool any_wall = __any_sync(full_warp, walks && !fluid_i);
        const int z0 = max(zlo - N, 0), z1 = min(zhi + N, g.nz - 1);
        for (int dx = -N; dx <= N; ++dx) {
            const int x = cx + dx;
            if (x < 0 || x >= g.nx) continue;
            for (int dy = -N; dy <= N; ++dy) {
                const int y = cy + dy;
                if (y < 0 || y >= g.ny) continue;
                const std::uint32_t column = g.encode(x, y, 0);
                const std::uint32_t b = in.cell_start[column + z0], e = in.cell_start[column + z1 + 1];
                for (std::uint32_t base = b; base < e; base += 32) {
                    __syncwarp();  // the previous batch is read
                    if (base + lane < e) {
                        cand_pos[lane] = in.pos[base + lane];
                        cand_cell[lane] = in.cell[base + lane];
                    }
                    __syncwarp();
                    const std::uint32_t batch = min(e - base, 32u);
                    for (std::uint32_t k = 0; k < batch; ++k) {
                        const std::uint32_t j = base + k;
                        const int dz = int(cand_cell[k] - column) - c.z;
                        bool keep = walks && j != me && dz >= -N && dz <= N;
                        if (keep) {
                            const real3 rij = separation(pos_i, cand_pos[k], dx, dy, dz, cs);
                            keep = dot(rij, rij) < reach2;
                        }
                        if (any_wall && keep && !fluid_i) keep = !is_boundary(in.velrho[j]);  // walls list fluid only
                        if (!keep) continue;
                        if (n < capacity) {
                            const std::uint32_t entry = CellOffsets ? ListEntry::encode(j, dx, dy, dz) : j;
                            if (n >= direct || n - stored >= StageRows) {
                                if (direct == 0xffffffffu) direct = n;
                                index[std::size_t(n) * stride + i] = entry;
                            } else {
                                ring[n % StageRows][lane] = entry;
                            }
                        }
                        ++n;
                    }
                }
                const std::uint32_t filled = __reduce_min_sync(full_warp, staging && walks ? n : 0xffffffffu);
                if (filled != 0xffffffffu) store_rows(filled);  // no walking lane stages: nothing to store
            }
        }
        store_rows(__reduce_max_sync(full_warp, staging && walks ? min(min(n, direct), capacity) : 0u));
    }
    if (valid) count[i] = n;
}

}  // namespace sph::gpu
