// Cluster lists (change 15 of docs/force-loop-notes.md): at a rebuild, the clusters of the
// sorted particles (one thread per column cuts its segments into clusters of at most 8), their
// boxes, each cluster's list of the clusters within reach (one thread per cluster), then each
// particle's Verlet list from its cluster's, each a thin kernel around the functions both
// backends share (neighbours/particle_clusters.hpp, physics/cluster_lists.hpp).
#include <cub/device/device_scan.cuh>

#include "backend/cuda_check.cuh"
#include "backend/cuda_cluster_lists.cuh"

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

// Each particle's list from its cluster's list of clusters: 8 lanes a cluster, aligned (thread
// 8c + s is particle s of cluster c, idle past the cluster's end). Each round the 8 lanes of a
// cluster load the listed cluster's particles once, coalesced, into shared memory, and every
// lane tests all of them from there (cluster_candidate_entry): a lane that loaded every
// candidate itself waited on the L1 70% of its time (change 15). The rows are stored as
// build_lists_in_step_kernel stores them: each lane stages its newest entries in a ring in
// shared memory, and after each round the warp stores the rows all its running lanes have
// filled, 128 coalesced bytes a row; a lane more than list_stage_rows ahead stores the rest
// itself, and walls store theirs from the start.
constexpr std::uint32_t list_stage_rows = 32;

template <bool CellOffsets>
__global__ void __launch_bounds__(block_size)
    build_lists_from_clusters_kernel(ForceInputs in, ClusterList list, std::uint32_t clusters, real reach2,
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
                               std::uint32_t n, cudaStream_t s) {
    SPH_CUDA_CHECK(cudaMemsetAsync(count, 0, std::size_t(n) * sizeof(std::uint32_t), s));
    if (n == 0 || list.stride == 0) return;
    if (in.grid.any_periodic() || in.cell_coords == nullptr)
        throw RunError("lists built from cluster lists need an open grid and the cell coordinates of their rebuild");
    const unsigned blocks = blocks_for(list.stride * cluster_size);
    if (cell_offsets)
        build_lists_from_clusters_kernel<true>
            <<<blocks, block_size, 0, s>>>(in, list, list.stride, reach2, index, count, stride, capacity);
    else
        build_lists_from_clusters_kernel<false>
            <<<blocks, block_size, 0, s>>>(in, list, list.stride, reach2, index, count, stride, capacity);
    SPH_CUDA_CHECK_LAUNCH();
}

}  // namespace sph::gpu
