// Cluster pair lists (list_layout = cluster): the clusters, their boxes, the lists and the force
// loop, each a thin kernel around the functions both backends share
// (neighbours/particle_clusters.hpp, physics/cluster_interaction.hpp). A prototype (change 14
// of docs/force-loop-notes.md): one thread per column cuts its segments into clusters, one
// thread per cluster builds its list, one thread per particle walks it; the lanes of a cluster
// read the same entries and the same j, so a warp's gathers touch a few places, not 32.
#include <cub/device/device_scan.cuh>
#include <cstdlib>
#include <type_traits>

#include "backend/cuda_check.cuh"
#include "backend/cuda_cluster_lists.cuh"
#include "physics/dispatch.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

__global__ void __launch_bounds__(block_size) column_cluster_count_kernel(const std::uint32_t* cell_start, GridView g,
                                                                          std::uint32_t* column_count) {
    const std::uint32_t columns = std::uint32_t(g.nx) * std::uint32_t(g.ny);
    const std::uint32_t col = blockIdx.x * blockDim.x + threadIdx.x;
    if (col < columns) column_count[col] = column_cluster_count(col, cell_start, g.nz);
    else if (col == columns) column_count[col] = 0;
}

__global__ void __launch_bounds__(block_size)
    fill_column_clusters_kernel(const std::uint32_t* cell_start, GridView g, const std::uint32_t* column_first,
                                std::uint32_t clusters, std::uint32_t* cluster_begin, std::uint32_t* cluster_of) {
    const std::uint32_t columns = std::uint32_t(g.nx) * std::uint32_t(g.ny);
    const std::uint32_t col = blockIdx.x * blockDim.x + threadIdx.x;
    if (col < columns) fill_column_clusters(col, cell_start, g.nz, column_first[col], cluster_begin, cluster_of);
    else if (col == columns) cluster_begin[clusters] = cell_start[g.cell_count()];
}

__global__ void __launch_bounds__(block_size) cluster_boxes_kernel(ForceInputs in, const std::uint32_t* cluster_begin,
                                                                   std::uint32_t clusters, ClusterBox* boxes) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= clusters) return;
    boxes[k] = cluster_box(cluster_begin[k], cluster_begin[k + 1], in.pos, in.velrho, in.cell, in.grid);
}

__global__ void __launch_bounds__(block_size)
    build_cluster_lists_kernel(const std::uint32_t* __restrict__ cell_start, GridView g, const ClusterBox* boxes,
                               const std::uint32_t* cluster_of, std::uint32_t clusters, real reach,
                               std::uint32_t* index, std::uint32_t* count, std::uint32_t capacity) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= clusters) return;
    count[k] = build_cluster_list(k, boxes, cluster_of, cell_start, g, reach, index, clusters, capacity).listed;
}

// Per-particle lists from the cluster lists (list_build = clusters, change 15): one thread per
// particle walks its cluster's listed clusters, as the cluster walk does (the 8 lanes of a
// cluster read the same entries and the same j: a warp's load touches ~4 places, where the
// stencil's build gathers 32), and keeps the candidates within the reach
// (cluster_candidate_entry). The rows are stored as build_lists_in_step_kernel stores them:
// each lane stages its newest entries in a ring in shared memory, and after each listed cluster
// the warp stores the rows all its running lanes have filled, 128 coalesced bytes a row; a lane
// more than list_stage_rows ahead stores the rest itself, and walls store theirs from the start.
template <bool CellOffsets, std::uint32_t list_stage_rows>
__global__ void __launch_bounds__(block_size)
    build_lists_from_clusters_kernel(ForceInputs in, ClusterList list, real reach2, std::uint32_t* index,
                                     std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity,
                                     ActiveRange range) {
    __shared__ std::uint32_t stage[block_size / 32][list_stage_rows][32];
    const std::uint32_t end = *range.end;
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t lane = threadIdx.x % 32, first = i - lane;
    if (first >= end) return;  // the whole warp is past the end
    const bool valid = i < end;
    const std::uint32_t me = valid ? i : end - 1;  // a lane past the end walks nothing
    auto& ring = stage[threadIdx.x / 32];
    const real4 pos_i = in.pos[me];
    const CellCoords own = in.cell_coords[me];
    const int3v ci{own.x, own.y, own.z};
    const bool walls_out = list_keeps_walls_out(me, in);
    const std::uint32_t c = list.cluster_of[me];
    const std::uint32_t listed = valid ? list.count[c] : 0;
    const std::uint32_t rounds = __reduce_max_sync(full_warp, listed);
    std::uint32_t n = 0;       // this lane's entries so far
    std::uint32_t stored = 0;  // rows [0, stored) of every staging lane are in index (warp-uniform)
    std::uint32_t direct = valid && !is_boundary(in.velrho[me]) ? 0xffffffffu : 0u;
    const bool staging = direct != 0;
    const auto store_rows = [&](std::uint32_t up_to) {
        const std::uint32_t mine = min(min(n, direct), capacity);
        for (std::uint32_t r = stored; r < up_to; ++r)
            if (valid && r < mine) index[std::size_t(r) * stride + i] = ring[r % list_stage_rows][lane];
        stored = up_to;
    };
    for (std::uint32_t k = 0; k < rounds; ++k) {
        if (k < listed) {
            const std::uint32_t cj = list.index[std::size_t(k) * list.stride + c];
            const std::uint32_t j0 = list.cluster_begin[cj], j1 = list.cluster_begin[cj + 1];
            for (std::uint32_t j = j0; j < j1; ++j) {
                const CellCoords q = in.cell_coords[j];
                std::uint32_t entry;
                if (!cluster_candidate_entry<CellOffsets>(me, j, pos_i, ci, in.pos[j], int3v{q.x, q.y, q.z}, walls_out,
                                                          in, reach2, entry))
                    continue;
                if (n < capacity) {
                    if (n >= direct || n - stored >= list_stage_rows) {
                        if (direct == 0xffffffffu) direct = n;
                        index[std::size_t(n) * stride + i] = entry;
                    } else {
                        ring[n % list_stage_rows][lane] = entry;
                    }
                }
                ++n;
            }
        }
        // Lanes whose walk has ended hold no row back (their last rows wait in the ring).
        const std::uint32_t filled = __reduce_min_sync(full_warp, staging && k < listed ? n : 0xffffffffu);
        if (filled != 0xffffffffu) store_rows(filled);
    }
    store_rows(__reduce_max_sync(full_warp, staging ? min(min(n, direct), capacity) : 0u));
    if (valid) count[i] = n;
}

// EXPERIMENT (branch only, SPH_EXP_GROUPED=1): the same lists with 8 lanes per cluster, aligned
// (thread 8c + s is particle s of cluster c, idle past the cluster's end): each round the 8
// lanes of a cluster load the listed cluster's particles once, coalesced, into shared memory
// and every lane tests all of them from there, where the kernel above has every lane load every
// candidate itself (ncu: 3.74 ms, stalled on the L1 70% of the time, 7% L1 hits).
template <bool CellOffsets, std::uint32_t list_stage_rows>
__global__ void __launch_bounds__(block_size)
    build_lists_from_clusters_grouped_kernel(ForceInputs in, ClusterList list, std::uint32_t clusters, real reach2,
                                             std::uint32_t* index, std::uint32_t* count, std::uint32_t stride,
                                             std::uint32_t capacity) {
    __shared__ std::uint32_t stage[block_size / 32][list_stage_rows][32];
    __shared__ real4 cand_pos[block_size / 32][32];
    __shared__ CellCoords cand_cell[block_size / 32][32];  // .unused: 1 for a wall
    const std::uint32_t g = blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t lane = threadIdx.x % 32, w = threadIdx.x / 32;
    if ((g - lane) / cluster_size >= clusters) return;  // the whole warp is past the end
    const bool in_cluster = g / cluster_size < clusters;
    const std::uint32_t c = in_cluster ? g / cluster_size : clusters - 1;
    const std::uint32_t slot = lane % cluster_size, group = lane - slot;
    const std::uint32_t b = list.cluster_begin[c], e = list.cluster_begin[c + 1];
    const std::uint32_t i = b + slot;
    const bool valid = in_cluster && i < e;
    const std::uint32_t me = valid ? i : b;
    auto& ring = stage[w];
    const real4 pos_i = in.pos[me];
    const CellCoords own = in.cell_coords[me];
    const int3v ci{own.x, own.y, own.z};
    const bool walls_out = list_keeps_walls_out(me, in);
    const bool any_walls_out = __any_sync(full_warp, valid && walls_out);
    const std::uint32_t listed = in_cluster ? list.count[c] : 0;
    const std::uint32_t rounds = __reduce_max_sync(full_warp, listed);
    std::uint32_t n = 0, stored = 0;
    std::uint32_t direct = valid && !is_boundary(in.velrho[me]) ? 0xffffffffu : 0u;
    const bool staging = direct != 0;
    const auto store_rows = [&](std::uint32_t up_to) {
        const std::uint32_t mine = min(min(n, direct), capacity);
        for (std::uint32_t r = stored; r < up_to; ++r)
            if (valid && r < mine) index[std::size_t(r) * stride + i] = ring[r % list_stage_rows][lane];
        stored = up_to;
    };
    for (std::uint32_t k = 0; k < rounds; ++k) {
        std::uint32_t j0 = 0, j1 = 0;
        if (k < listed) {
            const std::uint32_t cj = list.index[std::size_t(k) * list.stride + c];
            j0 = list.cluster_begin[cj];
            j1 = list.cluster_begin[cj + 1];
        }
        if (j0 + slot < j1) {
            const std::uint32_t j = j0 + slot;
            cand_pos[w][lane] = in.pos[j];
            CellCoords q = in.cell_coords[j];
            q.unused = any_walls_out && is_boundary(in.velrho[j]) ? 1 : 0;
            cand_cell[w][lane] = q;
        }
        __syncwarp();
        if (valid)
            for (std::uint32_t m = 0; m < j1 - j0; ++m) {
                const CellCoords q = cand_cell[w][group + m];
                std::uint32_t entry;
                if (!cluster_candidate_entry<CellOffsets>(me, j0 + m, pos_i, ci, cand_pos[w][group + m],
                                                          int3v{q.x, q.y, q.z}, false, in, reach2, entry))
                    continue;
                if (walls_out && q.unused) continue;
                if (n < capacity) {
                    if (n >= direct || n - stored >= list_stage_rows) {
                        if (direct == 0xffffffffu) direct = n;
                        index[std::size_t(n) * stride + i] = entry;
                    } else {
                        ring[n % list_stage_rows][lane] = entry;
                    }
                }
                ++n;
            }
        __syncwarp();  // every lane has read the candidates before the next round writes them
        const std::uint32_t filled = __reduce_min_sync(full_warp, staging && k < listed ? n : 0xffffffffu);
        if (filled != 0xffffffffu) store_rows(filled);
    }
    store_rows(__reduce_max_sync(full_warp, staging ? min(min(n, direct), capacity) : 0u));
    if (valid) count[i] = n;
}

// One thread per particle; the listed loop's launch policy (its loads; no lookahead, no entry
// offsets: a cluster entry is an index only).
template <class Kernel, bool Diffusion, class Policy, bool HitMasks>
__global__ void __launch_bounds__(Policy::block_size, Policy::min_blocks)
    forces_cluster_listed_kernel(ForceInputs in, ClusterList list, PhysicsParams p, real4* __restrict__ force) {
    const std::uint32_t i = blockIdx.x * Policy::block_size + threadIdx.x;
    if (i >= list.end) return;
    if (in.cell[i] >= in.grid.out_of_domain()) {  // left the domain since the last rebuild
        force[i] = real4{0, 0, 0, 0};
        return;
    }
    const Kernel kernel(p.h);
    force[i] = particle_force_cluster_listed<Kernel, Diffusion, Policy, HitMasks>(i, in, list, p, kernel);
}

}  // namespace

std::size_t cluster_scan_temp_bytes(std::uint32_t columns) {
    std::size_t bytes = 0;
    SPH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<const std::uint32_t*>(nullptr),
                                                 static_cast<std::uint32_t*>(nullptr), int(columns + 1)));
    return bytes;
}

std::uint32_t count_clusters(const ForceInputs& in, std::uint32_t* column_count, std::uint32_t* column_first,
                             void* temp, std::size_t temp_bytes, cudaStream_t s) {
    const std::uint32_t columns = std::uint32_t(in.grid.nx) * std::uint32_t(in.grid.ny);
    column_cluster_count_kernel<<<blocks_for(columns + 1), block_size, 0, s>>>(in.cell_start, in.grid, column_count);
    SPH_CUDA_CHECK_LAUNCH();
    SPH_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(temp, temp_bytes, column_count, column_first, int(columns + 1), s));
    std::uint32_t clusters = 0;
    SPH_CUDA_CHECK(cudaMemcpyAsync(&clusters, column_first + columns, sizeof clusters, cudaMemcpyDeviceToHost, s));
    SPH_CUDA_CHECK(cudaStreamSynchronize(s));
    return clusters;
}

void fill_clusters(const ForceInputs& in, const std::uint32_t* column_first, std::uint32_t clusters,
                   std::uint32_t* cluster_begin, std::uint32_t* cluster_of, ClusterBox* boxes, cudaStream_t s) {
    const std::uint32_t columns = std::uint32_t(in.grid.nx) * std::uint32_t(in.grid.ny);
    fill_column_clusters_kernel<<<blocks_for(columns + 1), block_size, 0, s>>>(in.cell_start, in.grid, column_first,
                                                                               clusters, cluster_begin, cluster_of);
    SPH_CUDA_CHECK_LAUNCH();
    if (clusters == 0) return;
    cluster_boxes_kernel<<<blocks_for(clusters), block_size, 0, s>>>(in, cluster_begin, clusters, boxes);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_cluster_lists(const ForceInputs& in, const ClusterBox* boxes, const std::uint32_t* cluster_of,
                         std::uint32_t clusters, real reach, std::uint32_t* index, std::uint32_t* count,
                         std::uint32_t capacity, cudaStream_t s) {
    if (clusters == 0) return;
    build_cluster_lists_kernel<<<blocks_for(clusters), block_size, 0, s>>>(in.cell_start, in.grid, boxes, cluster_of,
                                                                           clusters, reach, index, count, capacity);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_lists_from_clusters(const ForceInputs& in, const ClusterList& list, real reach2, std::uint32_t* index,
                               std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity, bool cell_offsets,
                               ActiveRange range, std::uint32_t n, cudaStream_t s) {
    SPH_CUDA_CHECK(cudaMemsetAsync(count, 0, std::size_t(n) * sizeof(std::uint32_t), s));
    if (n == 0) return;
    if (in.grid.any_periodic() || in.cell_coords == nullptr)
        throw RunError("lists built from cluster lists need an open grid and the cell coordinates of their rebuild");
    // EXPERIMENT (branch only): the ring's rows, 8, 16 or 32 (SPH_EXP_STAGE_ROWS): the ring takes
    // shared memory from the L1 that the candidates' loads would hit (ncu: 7% L1 hits with 32).
    static const int rows = [] {
        const char* e = std::getenv("SPH_EXP_STAGE_ROWS");
        return e ? std::atoi(e) : 32;
    }();
    static const bool grouped = [] {
        const char* e = std::getenv("SPH_EXP_GROUPED");
        return e && std::atoi(e) == 1;
    }();
    const auto launch = [&](auto offsets, auto stage_rows) {
        if (grouped)
            build_lists_from_clusters_grouped_kernel<decltype(offsets)::value, decltype(stage_rows)::value>
                <<<blocks_for(list.stride * cluster_size), block_size, 0, s>>>(in, list, list.stride, reach2, index,
                                                                             count, stride, capacity);
        else
            build_lists_from_clusters_kernel<decltype(offsets)::value, decltype(stage_rows)::value>
                <<<blocks_for(n), block_size, 0, s>>>(in, list, reach2, index, count, stride, capacity, range);
    };
    const auto with_rows = [&](auto offsets) {
        if (rows == 8) launch(offsets, std::integral_constant<std::uint32_t, 8>{});
        else if (rows == 16) launch(offsets, std::integral_constant<std::uint32_t, 16>{});
        else launch(offsets, std::integral_constant<std::uint32_t, 32>{});
    };
    if (cell_offsets) with_rows(std::true_type{});
    else with_rows(std::false_type{});
    SPH_CUDA_CHECK_LAUNCH();
}

void compute_forces_cluster_listed(const SubdomainConfig& cfg, const ForceInputs& in, const ClusterList& list,
                                   real4* force, cudaStream_t s) {
    if (list.end == 0) return;
    if (in.grid.any_periodic() || in.cell_coords == nullptr)
        throw RunError("cluster lists need an open grid and the cell coordinates their rebuild keeps");
    using Policy = ListedLoopPolicy;
    const bool hit_masks = cfg.variants.list_layout == ListLayoutVariant::cluster_hit_masks;
    dispatch_kernel(cfg.kernel, cfg.diffusion, [&](auto k, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        constexpr bool d = decltype(diffusion)::value;
        const unsigned blocks = blocks_for<Policy::block_size>(list.end);
        if (hit_masks)
            forces_cluster_listed_kernel<Kernel, d, Policy, true>
                <<<blocks, Policy::block_size, 0, s>>>(in, list, cfg.params, force);
        else
            forces_cluster_listed_kernel<Kernel, d, Policy, false>
                <<<blocks, Policy::block_size, 0, s>>>(in, list, cfg.params, force);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

}  // namespace sph::gpu
