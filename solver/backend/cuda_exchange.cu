// What a decomposition asks of a subdomain's particles: ghosts marked, a sorted cell range
// kept, received particles appended (CCCL's copy_if and count_if).
#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/execution_policy.h>
#include <thrust/iterator/zip_iterator.h>

#include "backend/cuda_check.cuh"
#include "backend/cuda_exchange.cuh"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

__global__ void mark_ghosts_kernel(const std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, std::uint32_t begin,
                                   std::uint32_t end, std::uint32_t out_of_domain) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < n) id[i] = mark_ghost(id[i], cell[i], begin, end, out_of_domain);
}

__global__ void clamp_cell_starts_kernel(std::uint32_t* cell_start, std::uint32_t* fluid_begin,
                                         std::uint32_t cell_count, std::uint32_t lo, std::uint32_t hi) {
    const std::uint32_t c = blockIdx.x * blockDim.x + threadIdx.x;
    if (c > cell_count) return;
    auto clamp = [&](std::uint32_t v) { return (v < lo ? lo : v > hi ? hi : v) - lo; };
    cell_start[c] = clamp(cell_start[c]);
    fluid_begin[c] = clamp(fluid_begin[c]);
}

struct CellIn {
    std::uint32_t begin, end;
    __host__ __device__ bool operator()(std::uint32_t c) const { return c >= begin && c < end; }
};

}  // namespace

void mark_ghosts(const std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, std::uint32_t begin, std::uint32_t end,
                 std::uint32_t out_of_domain, cudaStream_t s) {
    if (n == 0) return;
    mark_ghosts_kernel<<<blocks_for(n), block_size, 0, s>>>(cell, id, n, begin, end, out_of_domain);
    SPH_CUDA_CHECK_LAUNCH();
}

void clamp_cell_starts(std::uint32_t* cell_start, std::uint32_t* fluid_begin, std::uint32_t cell_count,
                       std::uint32_t lo, std::uint32_t hi, cudaStream_t s) {
    clamp_cell_starts_kernel<<<blocks_for(cell_count + 1), block_size, 0, s>>>(cell_start, fluid_begin, cell_count, lo, hi);
    SPH_CUDA_CHECK_LAUNCH();
}

ReceivedCount append_received_in(CarriedArrays from, std::uint32_t m, CarriedArrays to, std::uint32_t n,
                                 std::uint32_t begin, std::uint32_t end, std::uint32_t owned_begin,
                                 std::uint32_t owned_end, cudaStream_t s) {
    if (m == 0) return {};
    auto zip = [](const CarriedArrays& a, std::uint32_t at) {
        return thrust::make_zip_iterator(thrust::make_tuple(a.pos + at, a.velrho + at, a.velrho_prev + at, a.cell + at,
                                                            a.id + at));
    };
    const auto policy = thrust::cuda::par.on(s);
    const auto last = thrust::copy_if(policy, zip(from, 0), zip(from, m), from.cell, zip(to, n), CellIn{begin, end});
    SPH_CUDA_CHECK_LAUNCH();
    ReceivedCount c;
    c.kept = std::size_t(last - zip(to, n));
    c.owned = std::size_t(thrust::count_if(policy, from.cell, from.cell + m, CellIn{owned_begin, owned_end}));
    SPH_CUDA_CHECK_LAUNCH();
    return c;
}

}  // namespace sph::gpu
