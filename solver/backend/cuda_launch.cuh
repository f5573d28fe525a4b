#pragma once
// What every driver of the backend's kernels shares: the particles a kernel works on, the
// grid of a launch over them, and the mask of a whole warp.
#include <cstdint>

#include "backend/cuda_launch_policy.cuh"

namespace sph::gpu {

// The particles a kernel works on, as device pointers into cell_start: [*begin, *end). Kernels
// are launched over all n particles and skip the rest (particles that left the domain, ghosts
// of other subdomains) without a host round trip.
struct ActiveRange {
    const std::uint32_t* begin;
    const std::uint32_t* end;
};

// Every lane of a warp, for the *_sync intrinsics.
constexpr unsigned full_warp = 0xffffffffu;

// Blocks of BlockSize threads that cover n particles.
template <int BlockSize = ElementwisePolicy::block_size>
unsigned blocks_for(std::uint32_t n) {
    return (n + BlockSize - 1) / BlockSize;
}

}  // namespace sph::gpu
