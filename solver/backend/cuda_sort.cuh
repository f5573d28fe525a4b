#pragma once
// Drivers of the sort by (cell, id) and of the cell ranges built after it (cuda_sort.cu).
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "core/types.hpp"

namespace sph::gpu {

void make_sort_keys(const std::uint32_t* cell, const std::uint32_t* id, std::uint64_t* keys, std::uint32_t* order,
                    std::uint32_t n, cudaStream_t s);
// The real4 arrays a sort permutes: positions, velocity and density, the previous step's.
struct SortedArrays {
    real4* pos;
    real4* velrho;
    real4* velrho_prev;
};
void gather_sorted(const std::uint64_t* keys, const std::uint32_t* order, SortedArrays in, SortedArrays out,
                   std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, cudaStream_t s);
void build_cell_start(const std::uint32_t* sorted_cell, std::uint32_t n, std::uint32_t cell_count,
                      std::uint32_t* cell_start, cudaStream_t s);
// fluid_begin[c] = the first fluid particle of cell c, or cell_start[c + 1] when it has none
// (the sort puts each cell's boundary particles first).
void build_fluid_begin(const real4* sorted_velrho, const std::uint32_t* sorted_cell, const std::uint32_t* cell_start,
                       std::uint32_t n, std::uint32_t cell_count, std::uint32_t* fluid_begin, cudaStream_t s);

}  // namespace sph::gpu
