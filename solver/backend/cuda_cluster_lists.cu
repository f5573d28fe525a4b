// Cluster pair lists (list_layout = cluster): the clusters, their boxes, the lists and the force
// loop, each a thin kernel around the functions both backends share
// (neighbours/particle_clusters.hpp, physics/cluster_interaction.hpp). A prototype (change 14
// of docs/force-loop-notes.md): one thread per column cuts its segments into clusters, one
// thread per cluster builds its list, one thread per particle walks it; the lanes of a cluster
// read the same entries and the same j, so a warp's gathers touch a few places, not 32.
#include <cub/device/device_scan.cuh>

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
