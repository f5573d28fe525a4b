// The cell searches' loops: forces (per thread, or with each warp's pairs compacted), particle
// shifting's concentration gradient, and the search's work counters. Launch choices come from
// cuda_launch_policy.cuh, the variant from SubdomainConfig::variants.
#include <cub/block/block_reduce.cuh>

#include "backend/cuda_cell_forces.cuh"
#include "backend/cuda_check.cuh"
#include "backend/cuda_pair_queue.cuh"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

// The force loop: one thread per particle visiting its stencil (particle_force), walls only
// the fluid of each cell, each range in chunks of 32 candidates tested first and their
// neighbours' pair bodies run after (add_range_by_hit_masks). Four designs that gave the body
// fuller warps across ranges measured slower on an H200 (docs/force-loop-notes.md, changes
// 1, 2, 3 and 5); they are in git history.
template <class Kernel, class Search, bool Diffusion, class Policy>
__global__ void __launch_bounds__(Policy::block_size)
    forces_kernel(ForceInputs in, PhysicsParams p, real4* __restrict__ force, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * Policy::block_size + threadIdx.x;
    if (i >= *range.end) return;
    const Kernel kernel(p.h);
    force[i] = particle_force<Kernel, Search, Diffusion, Policy::template hit_masks<Search>>(i, in, p, kernel);
}

// The force loop with each warp's pairs compacted (cuda_pair_queue.cuh): the lanes walk
// their stencils in step (every lane the same (dx, dy[, dz]) sequence, a range outside the
// grid empty, each range's chunks as many as the warp's longest needs), test 32 candidates at
// a time and queue the pairs inside the support; the body runs on batches of 32 pairs. The
// same neighbours in the same order per particle as particle_force, and the same sums bit for
// bit. Warps of walls only keep the per-thread loop: their pairs are few and far between.
// A merged z-run across a periodic z face comes in pieces, which would break the lanes' step:
// the driver sends such grids to forces_kernel.
template <class Kernel, class Search, bool Diffusion, class Policy>
__global__ void __launch_bounds__(Policy::block_size)
    forces_compacted_kernel(ForceInputs in, PhysicsParams p, real4* __restrict__ force, ActiveRange range) {
    __shared__ PairQueueStorage queues[Policy::block_size / 32];
    const std::uint32_t end = *range.end;
    const std::uint32_t i = *range.begin + blockIdx.x * Policy::block_size + threadIdx.x;
    const std::uint32_t lane = threadIdx.x % 32, first = i - lane;
    if (first >= end) return;  // the whole warp is past the end
    const bool valid = i < end;
    const std::uint32_t me = valid ? i : end - 1;  // a lane past the end walks nothing
    const Kernel kernel(p.h);
    const real4 pos_i = in.pos[me];
    const bool fluid_i = !is_boundary(in.velrho[me]);
    if (__all_sync(full_warp, !valid || !fluid_i)) {
        if (valid) force[i] = particle_force<Kernel, Search, Diffusion, true>(i, in, p, kernel);
        return;
    }
    WarpPairQueue<Kernel, Diffusion> queue(queues[threadIdx.x / 32], in, p, kernel, first);
    PairTotals totals{fluid_i};
    const GridView& g = in.grid;
    // A wall particle keeps fluid neighbours only: a cell's range starts at its fluid, a
    // merged run holds each cell's walls, which the test drops.
    const bool walls_out = Search::merge && !fluid_i;
    Search::visit_ranges_in_step(
        g, in.cell_start, in.fluid_begin, g.decode(in.cell[me]), valid, !fluid_i,
        [&](std::uint32_t b, std::uint32_t e, int dx, int dy, typename Search::RangeZ z) {
            const auto dz_of = [&](std::uint32_t j) { return z.of(in.cell, j); };
            const RangeSeparation sep(pos_i, dx, dy, g.cell_size);
            const std::uint32_t len = e - b;
            const std::uint32_t longest = __reduce_max_sync(full_warp, len);
            for (std::uint32_t k0 = 0; k0 < longest; k0 += 32) {
                const std::uint32_t n = len > k0 ? (len - k0 < 32 ? len - k0 : 32) : 0;
                std::uint32_t hits = support_hits(in, p, sep, b + k0, n, dz_of);
                if (walls_out)
                    for (std::uint32_t m = hits; m != 0; m &= m - 1) {
                        const int k = lowest_set_bit(m);
                        if (is_boundary(in.velrho[b + k0 + k])) hits &= ~(1u << k);
                    }
                while (queue.push_round(hits, b + k0, dx, dy, dz_of, totals)) {
                }
            }
        });
    queue.flush(totals);
    if (valid) force[i] = totals.result(p);
}

template <class Kernel, class Search>
__global__ void __launch_bounds__(block_size) concentration_gradient_kernel(ForceInputs in, PhysicsParams p,
                                                                            real4* grad_c, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    const Kernel kernel(p.h);
    grad_c[i] = particle_concentration_gradient<Kernel, Search>(i, in, p, kernel);
}

template <class Search>
__global__ void count_work_kernel(ForceInputs in, PhysicsParams p, ActiveRange range,
                                  unsigned long long* counters) {
    using Reduce = cub::BlockReduce<unsigned long long, block_size>;
    __shared__ typename Reduce::TempStorage tmp[3];
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    SearchWork w;
    if (i < *range.end) w = particle_search_work<Search>(i, in, p);
    const auto c = Reduce(tmp[0]).Sum(w.candidates);
    const auto nb = Reduce(tmp[1]).Sum(w.neighbours);
    const auto r = Reduce(tmp[2]).Sum(w.ranges);
    if (threadIdx.x == 0) {
        atomicAdd(counters + 0, c);
        atomicAdd(counters + 1, nb);
        atomicAdd(counters + 2, r);
    }
}

}  // namespace

void compute_forces(const SubdomainConfig& cfg, const ForceInputs& in, real4* force, ActiveRange range,
                    std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    // force_loop = per-thread runs forces_kernel where the policy compacts: the loop merged
    // z-runs across a periodic z face need, selectable to test and time it on any grid.
    const bool per_thread = cfg.variants.force_loop == ForceLoopVariant::per_thread;
    dispatch_physics(cfg.kernel, cfg.diffusion, cfg.search, [&](auto k, auto srch, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        using Search = typename decltype(srch)::type;
        constexpr bool Diffusion = decltype(diffusion)::value;
        using Policy = ForceLoopPolicy;
        if constexpr (Policy::template compacted<Search>) {
            if (!(Search::merge && in.grid.periodic_z) && !per_thread) {
                forces_compacted_kernel<Kernel, Search, Diffusion, Policy>
                    <<<blocks_for<Policy::block_size>(n), Policy::block_size, 0, s>>>(in, cfg.params, force, range);
                return;
            }
        }
        forces_kernel<Kernel, Search, Diffusion, Policy>
            <<<blocks_for<Policy::block_size>(n), Policy::block_size, 0, s>>>(in, cfg.params, force, range);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

void concentration_gradient(const SubdomainConfig& cfg, const ForceInputs& in, real4* grad_c, ActiveRange range,
                            std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    dispatch_physics(cfg.kernel, false, cfg.search, [&](auto k, auto srch, auto) {
        using Kernel = typename decltype(k)::type;
        using Search = typename decltype(srch)::type;
        concentration_gradient_kernel<Kernel, Search><<<blocks_for(n), block_size, 0, s>>>(in, cfg.params, grad_c, range);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

void count_work(const SubdomainConfig& cfg, const ForceInputs& in, ActiveRange range, std::uint32_t n,
                unsigned long long* counters3, cudaStream_t s) {
    SPH_CUDA_CHECK(cudaMemsetAsync(counters3, 0, 3 * sizeof(unsigned long long), s));
    if (n == 0) return;
    dispatch_search(cfg.search, [&](auto srch) {
        using Search = typename decltype(srch)::type;
        count_work_kernel<Search><<<blocks_for(n), block_size, 0, s>>>(in, cfg.params, range, counters3);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

}  // namespace sph::gpu
