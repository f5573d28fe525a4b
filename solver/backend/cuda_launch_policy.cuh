#pragma once
// Launch choices of the CUDA kernels, kept apart from the kernels (CUB's tuning policies):
// block sizes, per GPU architecture. A kernel reads its policy as a template argument; the
// driver functions pick the policy for the GPU.
// Measured choices and their log: bench/FORCE_LOOP_NOTES.md.
namespace sph::gpu {

// The plain per-particle kernels (sort keys, gathers, advance, statistics).
struct ElementwisePolicy {
    static constexpr int block_size = 128;
};

// The force loop (cuda_kernels.cu, forces_kernel): one thread per particle.
struct ForceLoopPolicySm90 {
    static constexpr int block_size = 128;
};

// One architecture is tuned today (the build targets sm_90); a second one gets its own
// structs here and a switch on the device's compute capability in the drivers.
using ForceLoopPolicy = ForceLoopPolicySm90;

}  // namespace sph::gpu
