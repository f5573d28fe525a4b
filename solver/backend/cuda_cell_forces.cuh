#pragma once
// Drivers of the cell searches' loops (cuda_cell_forces.cu): forces, particle shifting's
// concentration gradient, and the search's work counters.
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "backend/subdomain.hpp"

namespace sph::gpu {

// The force loop the launch policy picks for cfg.search, or the per-thread loop where
// cfg.variants.force_loop says per-thread.
void compute_forces(const SubdomainConfig& cfg, const ForceInputs& in, real4* force, ActiveRange range,
                    std::uint32_t n, cudaStream_t s);
// Particle shifting's concentration gradient (cell search only).
void concentration_gradient(const SubdomainConfig& cfg, const ForceInputs& in, real4* grad_c, ActiveRange range,
                            std::uint32_t n, cudaStream_t s);
void count_work(const SubdomainConfig& cfg, const ForceInputs& in, ActiveRange range, std::uint32_t n,
                unsigned long long* counters3, cudaStream_t s);

}  // namespace sph::gpu
