#pragma once
// Launch choices of the CUDA kernels, kept apart from the kernels (CUB's tuning policies):
// block sizes, per GPU architecture. A kernel reads its policy as a template argument; the
// driver functions pick the policy for the GPU. The fallbacks a run may ask for instead of a
// policy's choice are the registry of implementation_variants.hpp, beside this one.
// Measured choices and their log: docs/force-loop-notes.md (choices measured slower are in
// git history, listed in its section "The variant registry").
namespace sph::gpu {

// The plain per-particle kernels (sort keys, gathers, advance, statistics).
struct ElementwisePolicy {
    static constexpr int block_size = 128;
};

// The force loop (cuda_cell_forces.cu, forces_kernel and forces_compacted_kernel): one thread
// per particle.
struct ForceLoopPolicySm90 {
    static constexpr int block_size = 128;
    // Whether the loop queues each warp's pairs and runs the body on full batches of 32
    // (forces_compacted_kernel, cuda_pair_queue.cuh) or runs it per thread (forces_kernel).
    // Measured (change 7): compacting wins on cells of the support (the body ran at 15 of 32
    // lanes: -12% a step on the dam break), and loses 8-20% on smaller cells, where the
    // per-thread loop's hit masks already keep 22 of 32 lanes busy and the queue's pushes and
    // drains cost more than the idle lanes did. The variant force_loop = per-thread runs the
    // per-thread loop everywhere.
    template <class Search>
    static constexpr bool compacted = Search::n == 1;
    // Whether the per-thread loop takes stencil ranges through add_range_by_hit_masks (test 32
    // candidates, then each lane's pair bodies) or candidate by candidate. Measured (change 6):
    // masks win on cells of the support (3-6%) and on merged runs of smaller cells (7-10%);
    // they lose 6% on smaller cells without merging (ranges of ~5 candidates) and 1% on merged
    // runs of cells of the support.
    template <class Search>
    static constexpr bool hit_masks = (Search::n == 1) != Search::merge;
};

// The listed loop (Verlet lists, forces_listed_kernel): one thread per particle. The members
// after block_size are physics/interaction.hpp's ListedLoopDefaults, chosen for this GPU.
struct ListedLoopPolicySm90 {
    static constexpr int block_size = 128;
    // __launch_bounds__' second argument: 9 blocks of 128 threads leave 56 registers a thread.
    // With 8 (64 registers) change 19's chunk loop took 61: 50% theoretical occupancy, 45.8%
    // achieved, 1.23 ms where its instructions at change 17's 51.5% predict ~1.10 (change 20,
    // unmeasured; the loop's Wendland variants spill 0-16 bytes of stack at 56).
    static constexpr int min_blocks = 9;
    // Measured (change 8): without the decode's two integer divisions an entry costs ~141
    // instructions, not ~167; the loop then waits on memory (72% of its stalls).
    static constexpr bool packed_cells = true;
    // Measured within 1% either way (change 8).
    static constexpr bool early_loads = true;
    // j's position and velocity-density in one whole load each, kept to the pair body: the
    // loop is bound by the L1's throughput, and nvcc otherwise gathered the density, the
    // velocity-density and the pressure in three loads, not one (change 10).
    static constexpr bool whole_loads = true;
    // The list read a chunk (four entries, one 16-byte load) at a time, the next chunk while
    // the current one is summed (change 17): a quarter of the list's load instructions, and as
    // far ahead as index_lookahead = 2 (one entry at a time, two ahead, until change 17).
    static constexpr bool chunk_loads = true;
    static constexpr int index_lookahead = 0;
    // Not a tuning but the list's layout: the driver takes WithEntryOffsets<> of this policy
    // where the lists carry cell offsets (gpu::lists_take_cell_offsets).
    static constexpr bool entry_offsets = false;
    // The lists built with a warp's lanes walking their stencils in step
    // (build_lists_in_step_kernel), so that a warp's rows are stored together (change 9). The
    // variant list_build = per-lane builds them lane by lane.
    static constexpr bool build_in_step = true;
};

// One architecture is tuned today (the build targets sm_90); a second one gets its own
// structs here and a switch on the device's compute capability in the drivers.
using ForceLoopPolicy = ForceLoopPolicySm90;
using ListedLoopPolicy = ListedLoopPolicySm90;

}  // namespace sph::gpu
