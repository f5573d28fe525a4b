// Cluster pair lists (list_layout = cluster): the boxes, the lists and the force loop, each a
// thin kernel around the functions both backends share (neighbours/particle_clusters.hpp,
// physics/cluster_interaction.hpp). A prototype (change 14 of docs/force-loop-notes.md): one
// thread per cluster builds its list, one thread per particle walks it; the 8 lanes of a
// cluster read the same entries and the same j, so a warp's gathers touch 4 places, not 32.
#include "backend/cuda_check.cuh"
#include "backend/cuda_cluster_lists.cuh"
#include "physics/dispatch.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

__global__ void __launch_bounds__(block_size) cluster_boxes_kernel(ForceInputs in, std::uint32_t first,
                                                                   std::uint32_t end, ClusterBox* boxes) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= cluster_count(first, end)) return;
    boxes[k] = cluster_box(k, first, end, in.pos, in.velrho, in.cell, in.grid);
}

__global__ void __launch_bounds__(block_size)
    build_cluster_lists_kernel(const std::uint32_t* __restrict__ cell_start, GridView g, const ClusterBox* boxes,
                               std::uint32_t first, std::uint32_t end, real reach, std::uint32_t* index,
                               std::uint32_t* count, std::uint32_t capacity) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t nc = cluster_count(first, end);
    if (k >= nc) return;
    count[k] = build_cluster_list(k, boxes, first, end, cell_start, g, reach, index, nc, capacity).listed;
}

// One thread per particle; the listed loop's launch policy (its loads; no lookahead, no entry
// offsets: a cluster entry is an index only).
template <class Kernel, bool Diffusion, class Policy>
__global__ void __launch_bounds__(Policy::block_size, Policy::min_blocks)
    forces_cluster_listed_kernel(ForceInputs in, ClusterList list, PhysicsParams p, real4* __restrict__ force) {
    const std::uint32_t i = list.first + blockIdx.x * Policy::block_size + threadIdx.x;
    if (i >= list.end) return;
    if (in.cell[i] >= in.grid.out_of_domain()) {  // left the domain since the last rebuild
        force[i] = real4{0, 0, 0, 0};
        return;
    }
    const Kernel kernel(p.h);
    force[i] = particle_force_cluster_listed<Kernel, Diffusion, Policy>(i, in, list, p, kernel);
}

}  // namespace

void fill_cluster_boxes(const ForceInputs& in, std::uint32_t first, std::uint32_t end, ClusterBox* boxes,
                        cudaStream_t s) {
    const std::uint32_t nc = cluster_count(first, end);
    if (nc == 0) return;
    cluster_boxes_kernel<<<blocks_for(nc), block_size, 0, s>>>(in, first, end, boxes);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_cluster_lists(const ForceInputs& in, const ClusterBox* boxes, std::uint32_t first, std::uint32_t end,
                         real reach, std::uint32_t* index, std::uint32_t* count, std::uint32_t capacity,
                         cudaStream_t s) {
    const std::uint32_t nc = cluster_count(first, end);
    if (nc == 0) return;
    build_cluster_lists_kernel<<<blocks_for(nc), block_size, 0, s>>>(in.cell_start, in.grid, boxes, first, end, reach,
                                                                     index, count, capacity);
    SPH_CUDA_CHECK_LAUNCH();
}

void compute_forces_cluster_listed(const SubdomainConfig& cfg, const ForceInputs& in, const ClusterList& list,
                                   real4* force, cudaStream_t s) {
    if (list.end <= list.first) return;
    if (in.grid.any_periodic() || in.cell_coords == nullptr)
        throw RunError("cluster lists need an open grid and the cell coordinates their rebuild keeps");
    using Policy = ListedLoopPolicy;
    dispatch_kernel(cfg.kernel, cfg.diffusion, [&](auto k, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        forces_cluster_listed_kernel<Kernel, decltype(diffusion)::value, Policy>
            <<<blocks_for<Policy::block_size>(list.end - list.first), Policy::block_size, 0, s>>>(in, list, cfg.params,
                                                                                               force);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

}  // namespace sph::gpu
