#pragma once
// Driver of the gauge kernels (cuda_gauges.cu): the per-point and per-particle functions of
// physics/gauges.hpp on the device, with deterministic sums (a fixed order per thread, then a
// fixed tree per block; no float atomics).
#include <cuda_runtime.h>

#include "backend/subdomain.hpp"

namespace sph::gpu {

// Each probe's partial sums over the owned particles into sums[k] (device memory):
//   probes         the probes, in device memory; host_probes the same, on the host
//   per_particle   device scratch of n entries (force probes: each particle's force)
void gauge_sums(const SubdomainConfig& cfg, const GaugeInputs& in, const GaugeProbe* probes,
                const std::vector<GaugeProbe>& host_probes, std::uint32_t n, real4* per_particle, GaugeSum* sums,
                cudaStream_t s);

}  // namespace sph::gpu
