// Time integration (one thread per particle) and the step's statistics in one CUB reduction.
#include <cub/device/device_reduce.cuh>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>

#include "backend/cuda_check.cuh"
#include "backend/cuda_integration.cuh"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

template <bool IntegrateBoundary>
__global__ void advance_kernel(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, KeptCells kept,
                               const real4* force, const real4* grad_c, TimeStep step, GridView g, PhysicsParams p,
                               ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    particle_advance<IntegrateBoundary>(i, pos, velrho, velrho_prev, cell, kept, force, grad_c, step, g, p);
}

// Per-particle statistics as an iterator, so one CUB reduction does all of them.
struct StatsOfParticle {
    const real4* velrho;
    const real4* velrho_prev;
    const real4* force;
    const std::uint32_t* id;
    ActiveRange range;
    TimeStep step;
    PhysicsParams p;
    StatsLimits lim;
    __device__ StepStats operator()(std::uint32_t i) const {
        if (i < *range.begin || i >= *range.end) return StepStats{};
        return particle_stats(i, velrho, velrho_prev, force, id, step, p, lim);
    }
};
struct MergeStats {
    __device__ StepStats operator()(const StepStats& a, const StepStats& b) const { return merge_stats(a, b); }
};

auto stats_iterator(const StatsOfParticle& op) {
    return thrust::make_transform_iterator(thrust::make_counting_iterator<std::uint32_t>(0), op);
}

}  // namespace

void advance(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, const KeptCells& kept,
             const real4* force, const real4* grad_c, const TimeStep& step, const SubdomainConfig& cfg,
             ActiveRange range, std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    if (cfg.integrate_boundary)
        advance_kernel<true><<<blocks_for(n), block_size, 0, s>>>(pos, velrho, velrho_prev, cell, kept, force, grad_c,
                                                                   step, cfg.grid, cfg.params, range);
    else
        advance_kernel<false><<<blocks_for(n), block_size, 0, s>>>(pos, velrho, velrho_prev, cell, kept, force, grad_c,
                                                                    step, cfg.grid, cfg.params, range);
    SPH_CUDA_CHECK_LAUNCH();
}

std::size_t reduce_stats_temp_bytes(std::uint32_t n) {
    std::size_t bytes = 0;
    SPH_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, stats_iterator(StatsOfParticle{}),
                                             static_cast<StepStats*>(nullptr), n, MergeStats{}, StepStats{}));
    return bytes;
}

void reduce_stats(const real4* velrho, const real4* velrho_prev, const real4* force, const std::uint32_t* id,
                  ActiveRange range, const TimeStep& step, const PhysicsParams& p, const StatsLimits& lim,
                  std::uint32_t n, void* temp, std::size_t temp_bytes, StepStats* out, cudaStream_t s) {
    const StatsOfParticle op{velrho, velrho_prev, force, id, range, step, p, lim};
    SPH_CUDA_CHECK(cub::DeviceReduce::Reduce(temp, temp_bytes, stats_iterator(op), out, n, MergeStats{}, StepStats{}, s));
}

}  // namespace sph::gpu
