#pragma once
// Drivers of the time integration and of the step's reductions (cuda_integration.cu).
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "backend/subdomain.hpp"

namespace sph::gpu {

// kept: what the listed loop reads of each particle's cell, kept up between rebuilds (KeptCells).
void advance(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, const KeptCells& kept,
             const real4* force, const real4* grad_c, const TimeStep& step, const SubdomainConfig& cfg,
             ActiveRange range, std::uint32_t n, cudaStream_t s);
// Bytes of temporary storage reduce_stats needs for n particles.
std::size_t reduce_stats_temp_bytes(std::uint32_t n);
void reduce_stats(const real4* velrho, const real4* velrho_prev, const real4* force, const std::uint32_t* id,
                  ActiveRange range, const TimeStep& step, const PhysicsParams& p, const StatsLimits& lim, std::uint32_t n, void* temp,
                  std::size_t temp_bytes, StepStats* out, cudaStream_t s);

}  // namespace sph::gpu
