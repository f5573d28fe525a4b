#pragma once
// Drivers of the cluster lists (cuda_cluster_lists.cu; change 15 of docs/force-loop-notes.md):
// the clusters of the sorted particles and their boxes, each cluster's list of clusters, and
// each particle's Verlet list from its cluster's.
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "backend/subdomain.hpp"
#include "physics/cluster_lists.hpp"

namespace sph::gpu {

// Temporary bytes count_clusters needs for a grid of `columns` (x, y) columns.
std::size_t cluster_scan_temp_bytes(std::uint32_t columns);
// Each column's cluster count (column_count, columns + 1 entries, the last one zero) and their
// exclusive sum (column_first): the first cluster of each column, and at [columns] how many
// clusters there are, which it returns (synchronises the stream).
std::uint32_t count_clusters(const ForceInputs& in, std::uint32_t* column_count, std::uint32_t* column_first,
                             void* temp, std::size_t temp_bytes, cudaStream_t s);
// Each cluster's first particle (cluster_begin, clusters + 1 entries, the last one the particles
// inside the domain), each particle's cluster (cluster_of) and each cluster's box.
void fill_clusters(const ForceInputs& in, const std::uint32_t* column_first, std::uint32_t clusters,
                   std::uint32_t* cluster_begin, std::uint32_t* cluster_of, ClusterBox* boxes, cudaStream_t s);
// Writes each cluster's list (column k of cluster c at index[k * clusters + c]) and count; the
// caller reduces the counts (longest_list) and grows the capacity.
void build_cluster_lists(const ForceInputs& in, const ClusterBox* boxes, const std::uint32_t* cluster_of,
                         std::uint32_t clusters, real reach, std::uint32_t* index, std::uint32_t* count,
                         std::uint32_t capacity, cudaStream_t s);
// Each particle's Verlet list (NeighbourList layout: column k of particle i at
// index[k * stride + i], count[i]; ListEntry codes with cell_offsets) from the cluster lists,
// for the particles in clusters (those inside the domain); the others' counts zero. The caller
// reduces the counts and grows the capacity, as after build_neighbour_lists.
void build_lists_from_clusters(const ForceInputs& in, const ClusterList& list, real reach2, std::uint32_t* index,
                               std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity, bool cell_offsets,
                               std::uint32_t n, cudaStream_t s);

}  // namespace sph::gpu
