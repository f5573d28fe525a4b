#pragma once
// Drivers of the Verlet lists (cuda_neighbour_lists.cu): what a rebuild fills and builds, the
// longest list, and the listed force loop.
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "backend/subdomain.hpp"

namespace sph::gpu {

// Whether a subdomain of n particles stores its lists with cell offsets (ListEntry): open
// grids, stencils of at most ListEntry::reach_cells, fewer than 2^23 particles in the run
// (cfg.particles_in_run, where set, else n), and not cfg.variants.list_entries = plain.
bool lists_take_cell_offsets(const SubdomainConfig& cfg, std::uint32_t n);
// Each particle's cell as coordinates, from the linear cells (after a sort), and, where kept
// has a build frame, its position as the frame's start.
void fill_cell_coords(const std::uint32_t* cell, const real4* pos, const KeptCells& kept, const GridView& g,
                      std::uint32_t n, cudaStream_t s);
// Writes each particle's list and count; returns nothing (the caller reduces the counts).
// cell_offsets writes ListEntry codes (searches of at most ListEntry::reach_cells a side).
// Built with a warp's lanes in step, or lane by lane where cfg.variants.list_build says
// per-lane or the stencil needs it.
void build_neighbour_lists(const SubdomainConfig& cfg, const ForceInputs& in, real reach2, std::uint32_t* index,
                           std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity, bool cell_offsets,
                           ActiveRange range, std::uint32_t n, cudaStream_t s);
// The longest list, on the host (synchronises the stream).
std::uint32_t longest_list(const std::uint32_t* count, std::uint32_t n, void* temp, std::size_t temp_bytes,
                           std::uint32_t* out, cudaStream_t s);
std::size_t longest_list_temp_bytes(std::uint32_t n);
void compute_forces_listed(const SubdomainConfig& cfg, const ForceInputs& in, const NeighbourList& list, real4* force,
                           ActiveRange range, std::uint32_t n, cudaStream_t s);

}  // namespace sph::gpu
