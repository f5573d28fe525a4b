// Probe kernels for the perf-check tests: the force loops of cuda_cell_forces.cu (cell search)
// and cuda_neighbour_lists.cu (stored list) on the real pair body, with the stand-ins of
// pair_probe.hpp. Compiled, never run: the tests read what the compiler made of them with
// tools/perf_check.py kernels.
#include "backend/cuda_launch_policy.cuh"
#include "pair_probe.hpp"

namespace sph::probe {

constexpr int block_size = 128;

__global__ void __launch_bounds__(block_size, SPH_PROBE_MIN_BLOCKS)
    probe_forces_kernel(ForceInputs in, PhysicsParams p, real4* __restrict__ force, std::uint32_t n) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const ProbeKernel kernel(p.h);
    force[i] = particle_force<ProbeKernel, ProbeSearch, true>(i, in, p, kernel);
}

__global__ void __launch_bounds__(block_size, SPH_PROBE_MIN_BLOCKS)
    probe_forces_listed_kernel(ForceInputs in, NeighbourList list, PhysicsParams p, real4* __restrict__ force,
                               std::uint32_t n) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const ProbeKernel kernel(p.h);
    force[i] = particle_force_listed<ProbeKernel, true, gpu::ListedLoopPolicy>(i, in, list, p, kernel);  // as forces_listed_kernel
}

}  // namespace sph::probe
