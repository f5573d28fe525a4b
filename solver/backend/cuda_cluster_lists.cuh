#pragma once
// Drivers of the cluster pair lists (cuda_cluster_lists.cu; list_layout = cluster, change 14 of
// docs/force-loop-notes.md): each cluster's bounding box, each cluster's list of clusters, and
// the force loop over them.
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "backend/subdomain.hpp"
#include "physics/cluster_interaction.hpp"

namespace sph::gpu {

// The boxes of the clusters of particles [first, end) (cluster_count(first, end) of them).
void fill_cluster_boxes(const ForceInputs& in, std::uint32_t first, std::uint32_t end, ClusterBox* boxes,
                        cudaStream_t s);
// Writes each cluster's list (column k of cluster c at index[k * stride + c], stride the cluster
// count) and count; the caller reduces the counts (longest_list) and grows the capacity.
void build_cluster_lists(const ForceInputs& in, const ClusterBox* boxes, std::uint32_t first, std::uint32_t end,
                         real reach, std::uint32_t* index, std::uint32_t* count, std::uint32_t capacity,
                         cudaStream_t s);
// The force loop over the cluster lists, one thread per particle of [list.first, list.end).
void compute_forces_cluster_listed(const SubdomainConfig& cfg, const ForceInputs& in, const ClusterList& list,
                                   real4* force, cudaStream_t s);

}  // namespace sph::gpu
