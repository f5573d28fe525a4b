#pragma once
// Launch choices of the CUDA kernels, kept apart from the kernels (CUB's tuning policies):
// block sizes, per GPU architecture. A kernel reads its policy as a template argument; the
// driver functions pick the policy for the GPU.
// Measured choices and their log: docs/force-loop-notes.md.
namespace sph::gpu {

// The plain per-particle kernels (sort keys, gathers, advance, statistics).
struct ElementwisePolicy {
    static constexpr int block_size = 128;
};

// Whether the force loop takes stencil ranges through add_range_by_hit_masks (test 32
// candidates, then each lane's pair bodies) or candidate by candidate. 2 (the default) is the
// choice per search measured on an H200 (docs/force-loop-notes.md, change 6); 0 and 1 force
// one way for every search at compile time, to time both on one GPU.
#ifndef SPH_FORCE_HIT_MASKS
#define SPH_FORCE_HIT_MASKS 2
#endif

// Whether the force loop queues each warp's pairs and runs the body on full batches of 32
// (forces_compacted_kernel, cuda_pair_queue.cuh) or runs it per thread (forces_kernel). 2 (the
// default) is the choice per search measured on an H200 (docs/force-loop-notes.md, change 7);
// 1 compacts for every search and 0 never (SPH_FORCE_LOOP=per-thread at run time also
// forces the per-thread loop, to time both on one build).
#ifndef SPH_FORCE_COMPACT
#define SPH_FORCE_COMPACT 2
#endif

// The force loop (cuda_kernels.cu, forces_kernel and forces_compacted_kernel): one thread per particle.
struct ForceLoopPolicySm90 {
    static constexpr int block_size = 128;
    // Measured: compacting wins on cells of the support (the body ran at 15 of 32 lanes:
    // -12% a step on the dam break), and loses 8-20% on smaller cells, where the per-thread
    // loop's hit masks already keep 22 of 32 lanes busy and the queue's pushes and drains
    // cost more than the idle lanes did.
    template <class Search>
    static constexpr bool compacted = SPH_FORCE_COMPACT == 2 ? Search::n == 1 : SPH_FORCE_COMPACT != 0;
    // Measured: masks win on cells of the support (3-6%) and on merged runs of smaller cells
    // (7-10%); they lose 6% on smaller cells without merging (ranges of ~5 candidates) and 1%
    // on merged runs of cells of the support.
    template <class Search>
    static constexpr bool hit_masks = SPH_FORCE_HIT_MASKS == 2 ? (Search::n == 1) != Search::merge
                                                               : SPH_FORCE_HIT_MASKS != 0;
};

// The listed loop (Verlet lists, forces_listed_kernel): one thread per particle. The members
// after block_size are physics/interaction.hpp's ListedLoopDefaults, chosen for this GPU.
struct ListedLoopPolicySm90 {
    static constexpr int block_size = 128;
    // __launch_bounds__' second argument: 8 blocks of 128 threads leave 64 registers a thread
    // (without it the lookahead's loop took 71: 44% occupancy where 56 registers gave 52%).
    static constexpr int min_blocks = 8;
    // Measured (change 8): without the decode's two integer divisions an entry costs ~141
    // instructions, not ~167; the loop then waits on memory (72% of its stalls).
    static constexpr bool packed_cells = true;
    // Measured within 1% either way (change 8).
    static constexpr bool early_loads = true;
    // j's position and velocity-density in one whole load each, kept to the pair body: the
    // loop is bound by the L1's throughput, and nvcc otherwise gathered the density, the
    // velocity-density and the pressure in three loads, not one (change 10).
    static constexpr bool whole_loads = true;
    static constexpr int index_lookahead = 2;
    // Not a tuning but the list's layout: the driver takes WithEntryOffsets<> of this policy
    // where the lists carry cell offsets (gpu::lists_take_cell_offsets).
    static constexpr bool entry_offsets = false;
    // The lists built with a warp's lanes walking their stencils in step
    // (build_lists_in_step_kernel), so that a warp's rows are stored together.
    static constexpr bool build_in_step = true;
};
// Variants that SPH_LISTED_POLICY names at run time, to time them on one build.
struct ListedLoopNoLookahead : ListedLoopPolicySm90 {  // "no-lookahead"
    static constexpr int index_lookahead = 0;
};
struct ListedLoopSplitLoads : ListedLoopPolicySm90 {  // "split-loads": as nvcc places them
    static constexpr bool whole_loads = false;
};

// One architecture is tuned today (the build targets sm_90); a second one gets its own
// structs here and a switch on the device's compute capability in the drivers.
using ForceLoopPolicy = ForceLoopPolicySm90;
using ListedLoopPolicy = ListedLoopPolicySm90;

}  // namespace sph::gpu
