// Sort by (cell, id) and the cell ranges built after it: thin kernels and a CCCL search.
#include <thrust/binary_search.h>
#include <thrust/execution_policy.h>
#include <thrust/iterator/counting_iterator.h>

#include "backend/cuda_check.cuh"
#include "backend/cuda_sort.cuh"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

__global__ void make_sort_keys_kernel(const std::uint32_t* cell, const std::uint32_t* id, std::uint64_t* keys,
                                      std::uint32_t* order, std::uint32_t n) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    keys[i] = (std::uint64_t(cell[i]) << 32) | id[i];
    order[i] = i;
}

__global__ void gather_sorted_kernel(const std::uint64_t* keys, const std::uint32_t* order, SortedArrays in,
                                     SortedArrays out, std::uint32_t* cell, std::uint32_t* id, std::uint32_t n) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= n) return;
    const std::uint32_t j = order[k];
    out.pos[k] = in.pos[j];
    out.velrho[k] = in.velrho[j];
    out.velrho_prev[k] = in.velrho_prev[j];
    const std::uint64_t key = keys[k];
    cell[k] = std::uint32_t(key >> 32);
    id[k] = std::uint32_t(key);
}


__global__ void fluid_begin_init_kernel(const std::uint32_t* cell_start, std::uint32_t* fluid_begin,
                                        std::uint32_t cell_count) {
    const std::uint32_t c = blockIdx.x * blockDim.x + threadIdx.x;
    if (c <= cell_count) fluid_begin[c] = c < cell_count ? cell_start[c + 1] : cell_start[c];
}

// The first fluid particle of a cell is the one whose predecessor is a boundary particle or
// lies in another cell (each cell holds its boundary particles first).
__global__ void fluid_begin_mark_kernel(const real4* velrho, const std::uint32_t* cell, std::uint32_t* fluid_begin,
                                        std::uint32_t n, std::uint32_t cell_count) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= n) return;
    const std::uint32_t c = cell[k];
    if (c >= cell_count || is_boundary(velrho[k])) return;
    if (k == 0 || cell[k - 1] != c || is_boundary(velrho[k - 1])) fluid_begin[c] = k;
}

}  // namespace

void make_sort_keys(const std::uint32_t* cell, const std::uint32_t* id, std::uint64_t* keys, std::uint32_t* order,
                    std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    make_sort_keys_kernel<<<blocks_for(n), block_size, 0, s>>>(cell, id, keys, order, n);
    SPH_CUDA_CHECK_LAUNCH();
}

void gather_sorted(const std::uint64_t* keys, const std::uint32_t* order, SortedArrays in, SortedArrays out,
                   std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    gather_sorted_kernel<<<blocks_for(n), block_size, 0, s>>>(keys, order, in, out, cell, id, n);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_cell_start(const std::uint32_t* sorted_cell, std::uint32_t n, std::uint32_t cell_count,
                      std::uint32_t* cell_start, cudaStream_t s) {
    // cell_start[c] = first sorted particle whose cell is >= c, for c = 0 .. cell_count.
    thrust::lower_bound(thrust::cuda::par_nosync.on(s), sorted_cell, sorted_cell + n,
                        thrust::make_counting_iterator<std::uint32_t>(0),
                        thrust::make_counting_iterator<std::uint32_t>(cell_count + 1), cell_start);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_fluid_begin(const real4* sorted_velrho, const std::uint32_t* sorted_cell, const std::uint32_t* cell_start,
                       std::uint32_t n, std::uint32_t cell_count, std::uint32_t* fluid_begin, cudaStream_t s) {
    fluid_begin_init_kernel<<<blocks_for(cell_count + 1), block_size, 0, s>>>(cell_start, fluid_begin, cell_count);
    SPH_CUDA_CHECK_LAUNCH();
    if (n == 0) return;
    fluid_begin_mark_kernel<<<blocks_for(n), block_size, 0, s>>>(sorted_velrho, sorted_cell, fluid_begin, n, cell_count);
    SPH_CUDA_CHECK_LAUNCH();
}

}  // namespace sph::gpu
