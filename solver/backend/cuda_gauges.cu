// The gauge kernels: one block per point probe (its threads walk the stencil's cells, each
// in a fixed order, then a fixed tree joins them); a force probe is a pass over the particles
// (each the fluid's force on it, zero off the body) and one block that sums it in a fixed order.
#include "backend/cuda_check.cuh"
#include "backend/cuda_gauges.cuh"
#include "core/smoothing_kernels.hpp"

namespace sph::gpu {
namespace {

constexpr int gauge_block = 128;

// Joins the block's partial sums in shared memory by a fixed tree; thread 0 gets the total.
__device__ GaugeSum block_merge(GaugeKind kind, GaugeSum mine, GaugeSum* shared) {
    shared[threadIdx.x] = mine;
    __syncthreads();
    for (int half = gauge_block / 2; half > 0; half /= 2) {
        if (int(threadIdx.x) < half)
            shared[threadIdx.x] = merge_gauge_sums(kind, shared[threadIdx.x], shared[threadIdx.x + half]);
        __syncthreads();
    }
    return shared[0];
}

template <class Kernel>
__global__ void __launch_bounds__(gauge_block) point_probe_kernel(GaugeInputs in, PhysicsParams p,
                                                                  const GaugeProbe* probes, GaugeSum* sums) {
    __shared__ GaugeSum shared[gauge_block];
    const GaugeProbe probe = probes[blockIdx.x];
    if (probe.kind == GaugeKind::force) return;  // the whole block leaves together
    const Kernel kernel(p.h);
    const GaugeStencil st = probe_stencil(probe, in.particles.grid, p);
    GaugeSum mine = empty_gauge_sum(probe.kind);
    for (std::uint32_t c = threadIdx.x; c < st.cells(); c += gauge_block)
        mine = merge_gauge_sums(probe.kind, mine, probe_cell_sum(probe, in, p, kernel, st.cell(in.particles.grid, c)));
    const GaugeSum total = block_merge(probe.kind, mine, shared);
    if (threadIdx.x == 0) sums[blockIdx.x] = total;
}

template <class Kernel>
__global__ void __launch_bounds__(gauge_block) body_force_kernel(GaugeInputs in, PhysicsParams p, GaugeProbe probe,
                                                                 real4* per_particle, std::uint32_t n) {
    const std::uint32_t i = blockIdx.x * gauge_block + threadIdx.x;
    if (i >= n) return;
    real3 f = make3(0, 0, 0);
    if (i >= in.owned_begin() && i < in.owned_end()) f = fluid_force_on_body(i, probe, in, p, Kernel(p.h));
    per_particle[i] = make4(f, 0);
}

__global__ void __launch_bounds__(gauge_block) sum_force_kernel(GaugeInputs in, const real4* per_particle,
                                                                GaugeSum* out) {
    __shared__ GaugeSum shared[gauge_block];
    GaugeSum mine;
    for (std::uint32_t i = in.owned_begin() + threadIdx.x; i < in.owned_end(); i += gauge_block) {
        const real4 f = per_particle[i];
        mine.v[0] += double(f.x);
        mine.v[1] += double(f.y);
        mine.v[2] += double(f.z);
    }
    const GaugeSum total = block_merge(GaugeKind::force, mine, shared);
    if (threadIdx.x == 0) *out = total;
}

template <class Kernel>
void launch(const GaugeInputs& in, const PhysicsParams& p, const GaugeProbe* probes,
            const std::vector<GaugeProbe>& host_probes, std::uint32_t n, real4* per_particle, GaugeSum* sums,
            cudaStream_t s) {
    const std::uint32_t count = std::uint32_t(host_probes.size());
    point_probe_kernel<Kernel><<<count, gauge_block, 0, s>>>(in, p, probes, sums);
    SPH_CUDA_CHECK_LAUNCH();
    for (std::uint32_t k = 0; k < count; ++k) {
        if (host_probes[k].kind != GaugeKind::force) continue;
        if (n == 0) {
            SPH_CUDA_CHECK(cudaMemsetAsync(sums + k, 0, sizeof(GaugeSum), s));
            continue;
        }
        body_force_kernel<Kernel><<<(n + gauge_block - 1) / gauge_block, gauge_block, 0, s>>>(in, p, host_probes[k],
                                                                                               per_particle, n);
        SPH_CUDA_CHECK_LAUNCH();
        sum_force_kernel<<<1, gauge_block, 0, s>>>(in, per_particle, sums + k);
        SPH_CUDA_CHECK_LAUNCH();
    }
}

}  // namespace

void gauge_sums(const SubdomainConfig& cfg, const GaugeInputs& in, const GaugeProbe* probes,
                const std::vector<GaugeProbe>& host_probes, std::uint32_t n, real4* per_particle, GaugeSum* sums,
                cudaStream_t s) {
    if (host_probes.empty()) return;
    if (cfg.kernel == KernelType::wendland) launch<WendlandC2>(in, cfg.params, probes, host_probes, n, per_particle, sums, s);
    else launch<CubicSpline>(in, cfg.params, probes, host_probes, n, per_particle, sums, s);
}

}  // namespace sph::gpu
