#pragma once
// Launch choices of the CUDA kernels, kept apart from the kernels (CUB's tuning policies):
// block sizes, per GPU architecture. A kernel reads
// its policy as a template argument; the driver functions pick the policy for the GPU.
// Measured choices and their log: bench/FORCE_LOOP_NOTES.md.
namespace sph::gpu {

// The plain per-particle kernels (sort keys, gathers, advance, statistics).
struct ElementwisePolicy {
    static constexpr int block_size = 128;
};

// The force loop (cuda_kernels.cu, forces_deferred_kernel and forces_kernel): one thread per
// particle. The deferred loop's threads each own a column of `chunk` neighbour slots in
// shared memory (6 bytes a slot: the index and the packed cell offset): 24 KiB a block for
// 128 x 32, which keeps 8 blocks (1024 threads) of an SM of Hopper's 228 KiB resident. The
// lanes drain their buffers through the pair body when one holds `drain_at` neighbours after a
// stencil range; half the buffer leaves room for the next range's hits before a lane must drain
// alone.
struct ForceLoopPolicySm90 {
    static constexpr int block_size = 128;
    static constexpr int chunk = 32;
    static constexpr int drain_at = 16;
};

// The searches without a gather step (Verlet lists, list builds, work counters, shifting).
struct NeighbourLoopPolicySm90 {
    static constexpr int block_size = 128;
};

// One architecture is tuned today (the build targets sm_90); a second one gets its own
// structs here and a switch on the device's compute capability in the drivers.
using ForceLoopPolicy = ForceLoopPolicySm90;
using NeighbourLoopPolicy = NeighbourLoopPolicySm90;

}  // namespace sph::gpu
