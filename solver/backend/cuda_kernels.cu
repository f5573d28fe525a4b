// CUDA kernels: thin wrappers that run the shared per-particle functions, one thread per
// particle, plus the CCCL calls that build cell ranges and reductions. Launch choices (block
// sizes, the force loop's neighbour buffer) come from cuda_launch_policy.cuh.
#include <cstdlib>
#include <string>

#include <cub/block/block_reduce.cuh>
#include <cub/device/device_reduce.cuh>
#include <thrust/binary_search.h>
#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/execution_policy.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>
#include <thrust/iterator/zip_iterator.h>


#include "backend/cuda_drivers.cuh"
#include "backend/cuda_check.cuh"
#include "backend/cuda_launch_policy.cuh"
#include "backend/cuda_pair_queue.cuh"
#include "backend/cuda_warp_stencil_build.cuh"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;
template <int BlockSize = block_size>
unsigned blocks_for(std::uint32_t n) { return (n + BlockSize - 1) / BlockSize; }

__global__ void make_sort_keys_kernel(const std::uint32_t* cell, const std::uint32_t* id, std::uint64_t* keys,
                                      std::uint32_t* order, std::uint32_t n) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    keys[i] = (std::uint64_t(cell[i]) << 32) | id[i];
    order[i] = i;
}

__global__ void gather_sorted_kernel(const std::uint64_t* keys, const std::uint32_t* order, SortedArrays in,
                                     SortedArrays out, std::uint32_t* cell, std::uint32_t* id, std::uint32_t n) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= n) return;
    const std::uint32_t j = order[k];
    out.pos[k] = in.pos[j];
    out.velrho[k] = in.velrho[j];
    out.velrho_prev[k] = in.velrho_prev[j];
    const std::uint64_t key = keys[k];
    cell[k] = std::uint32_t(key >> 32);
    id[k] = std::uint32_t(key);
}

__global__ void mark_ghosts_kernel(const std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, std::uint32_t begin,
                                   std::uint32_t end, std::uint32_t out_of_domain) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < n) id[i] = mark_ghost(id[i], cell[i], begin, end, out_of_domain);
}

__global__ void fluid_begin_init_kernel(const std::uint32_t* cell_start, std::uint32_t* fluid_begin,
                                        std::uint32_t cell_count) {
    const std::uint32_t c = blockIdx.x * blockDim.x + threadIdx.x;
    if (c <= cell_count) fluid_begin[c] = c < cell_count ? cell_start[c + 1] : cell_start[c];
}

// The first fluid particle of a cell is the one whose predecessor is a boundary particle or
// lies in another cell (each cell holds its boundary particles first).
__global__ void fluid_begin_mark_kernel(const real4* velrho, const std::uint32_t* cell, std::uint32_t* fluid_begin,
                                        std::uint32_t n, std::uint32_t cell_count) {
    const std::uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= n) return;
    const std::uint32_t c = cell[k];
    if (c >= cell_count || is_boundary(velrho[k])) return;
    if (k == 0 || cell[k - 1] != c || is_boundary(velrho[k - 1])) fluid_begin[c] = k;
}

__global__ void clamp_cell_starts_kernel(std::uint32_t* cell_start, std::uint32_t* fluid_begin,
                                         std::uint32_t cell_count, std::uint32_t lo, std::uint32_t hi) {
    const std::uint32_t c = blockIdx.x * blockDim.x + threadIdx.x;
    if (c > cell_count) return;
    auto clamp = [&](std::uint32_t v) { return (v < lo ? lo : v > hi ? hi : v) - lo; };
    cell_start[c] = clamp(cell_start[c]);
    fluid_begin[c] = clamp(fluid_begin[c]);
}

struct CellIn {
    std::uint32_t begin, end;
    __host__ __device__ bool operator()(std::uint32_t c) const { return c >= begin && c < end; }
};

// The force loop: one thread per particle visiting its stencil (particle_force), walls only
// the fluid of each cell, each range in chunks of 32 candidates tested first and their
// neighbours' pair bodies run after (add_range_by_hit_masks). Four designs that gave the body
// fuller warps across ranges measured slower on an H200 (bench/FORCE_LOOP_NOTES.md, changes
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

template <class Search, bool CellOffsets>
__global__ void __launch_bounds__(block_size) build_lists_kernel(ForceInputs in, real reach2, std::uint32_t* index,
                                                                 std::uint32_t* count, std::uint32_t stride,
                                                                 std::uint32_t capacity, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    count[i] = build_particle_list<Search, CellOffsets>(i, in, reach2, index, stride, capacity);
}

// The listed loop: one thread per particle over its stored list, cells read as coordinates.
// The same lists, built with a warp's lanes walking their stencils in step
// (visit_ranges_in_step, as forces_compacted_kernel) and their rows stored together: each
// lane keeps its newest entries in shared memory (a ring of list_stage_rows rows), and after
// every range the warp stores the rows that all its lanes have filled, 128 coalesced bytes a
// row. Stored lane by lane (build_lists_kernel), each 4-byte entry went to DRAM as a
// partly written 32-byte sector: 6.8 GB moved for a 0.8 GB list on the dam break, ~6.5 of a
// rebuild's 8.2 ms (FORCE_LOOP_NOTES.md, change 9). A lane more than list_stage_rows ahead of
// the warp's slowest stores the rest of its list itself, and walls store theirs from the start.
// The same candidates in the same order (the StepwiseRanges test), so the same lists; not for
// merged runs across a periodic z face, which come in pieces (the driver keeps the other
// kernel there). CellOffsets stores ListEntry codes, as build_particle_list.
constexpr std::uint32_t list_stage_rows = 32;  // 16 KB a block: 46 registers, not shared memory, then bound the occupancy

template <class Search, bool CellOffsets>
__global__ void __launch_bounds__(block_size)
    build_lists_in_step_kernel(ForceInputs in, real reach2, std::uint32_t* index, std::uint32_t* count,
                               std::uint32_t stride, std::uint32_t capacity, ActiveRange range) {
    __shared__ std::uint32_t stage[block_size / 32][list_stage_rows][32];
    const std::uint32_t end = *range.end;
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t lane = threadIdx.x % 32, first = i - lane;
    if (first >= end) return;  // the whole warp is past the end
    const bool valid = i < end;
    const std::uint32_t me = valid ? i : end - 1;  // a lane past the end walks nothing
    auto& ring = stage[threadIdx.x / 32];
    const real4 pos_i = in.pos[me];
    const bool fluid_i = !is_boundary(in.velrho[me]);
    const GridView& g = in.grid;
    // A wall lists fluid only (build_particle_list): a cell's range starts at its fluid, a
    // merged run holds each cell's walls, which the test drops.
    const bool walls_out = Search::merge && !fluid_i;
    std::uint32_t n = 0;                    // this lane's entries so far
    std::uint32_t stored = 0;               // rows [0, stored) of every staging lane are in index (warp-uniform)
    // This lane stores its rows from here on itself. A wall lists fluid only, a few entries
    // where the fluid lanes of its warp list ~200: it stores its own from the start and does not
    // count in the warp's filled rows. The expected gain (fluid lanes no longer running past the
    // ring behind a wall) did not show: the build took the same time either way (change 9).
    std::uint32_t direct = valid && fluid_i ? 0xffffffffu : 0u;
    const bool staging = direct != 0;
    // Rows [stored, up_to) of every lane that staged them, into index.
    const auto store_rows = [&](std::uint32_t up_to) {
        const std::uint32_t mine = min(min(n, direct), capacity);
        for (std::uint32_t r = stored; r < up_to; ++r)
            if (valid && r < mine) index[std::size_t(r) * stride + i] = ring[r % list_stage_rows][lane];
        stored = up_to;
    };
    Search::visit_ranges_in_step(
        g, in.cell_start, in.fluid_begin, g.decode(in.cell[me]), valid, !fluid_i,
        [&](std::uint32_t b, std::uint32_t e, int dx, int dy, typename Search::RangeZ z) {
            for (std::uint32_t j = b; j < e; ++j) {
                const int dz = z.of(in.cell, j);
                const real3 rij = separation(pos_i, in.pos[j], dx, dy, dz, g.cell_size);
                if (j == me || dot(rij, rij) >= reach2 || (walls_out && is_boundary(in.velrho[j]))) continue;
                if (n < capacity) {
                    const std::uint32_t entry = CellOffsets ? ListEntry::encode(j, dx, dy, dz) : j;
                    if (n >= direct || n - stored >= list_stage_rows) {
                        if (direct == 0xffffffffu) direct = n;
                        index[std::size_t(n) * stride + i] = entry;
                    } else {
                        ring[n % list_stage_rows][lane] = entry;
                    }
                }
                ++n;
            }
            const std::uint32_t filled = __reduce_min_sync(full_warp, staging ? n : 0xffffffffu);
            if (filled != 0xffffffffu) store_rows(filled);  // no lane of the warp stages: nothing to store
        });
    store_rows(__reduce_max_sync(full_warp, staging ? min(min(n, direct), capacity) : 0u));
    if (valid) count[i] = n;
}

template <class Kernel, bool Diffusion, class Policy>
__global__ void __launch_bounds__(Policy::block_size, Policy::min_blocks)
    forces_listed_kernel(ForceInputs in, NeighbourList list, PhysicsParams p, real4* __restrict__ force,
                         ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * Policy::block_size + threadIdx.x;
    if (i >= *range.end) return;
    if (in.cell[i] >= in.grid.out_of_domain()) {  // left the domain since the last rebuild
        force[i] = real4{0, 0, 0, 0};
        return;
    }
    const Kernel kernel(p.h);
    force[i] = particle_force_listed<Kernel, Diffusion, Policy>(i, in, list, p, kernel);
}

template <bool IntegrateBoundary>
__global__ void advance_kernel(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, KeptCells kept,
                               const real4* force, const real4* grad_c, TimeStep step, GridView g, PhysicsParams p,
                               ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    particle_advance<IntegrateBoundary>(i, pos, velrho, velrho_prev, cell, kept, force, grad_c, step, g, p);
}

__global__ void cell_coords_kernel(const std::uint32_t* cell, const real4* pos, KeptCells kept, GridView g,
                                   std::uint32_t n) {
    const std::uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const std::uint32_t c = cell[i];
    const bool inside = c < g.out_of_domain();
    kept.coords[i] = pack_cell_coords(g.decode(c), inside);
    if (kept.build_frame)
        kept.build_frame[i] = inside ? pos[i] : real4{real(1e15), real(1e15), real(1e15), pos[i].w};
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

// Per-particle statistics as an iterator, so one CUB reduction does all of them.
struct StatsOfParticle {
    const real4* velrho;
    const real4* velrho_prev;
    const real4* force;
    const std::uint32_t* id;
    ActiveRange range;
    TimeStep step;
    PhysicsParams p;
    StatsLimits lim;
    __device__ StepStats operator()(std::uint32_t i) const {
        if (i < *range.begin || i >= *range.end) return StepStats{};
        return particle_stats(i, velrho, velrho_prev, force, id, step, p, lim);
    }
};
struct MergeStats {
    __device__ StepStats operator()(const StepStats& a, const StepStats& b) const { return merge_stats(a, b); }
};

auto stats_iterator(const StatsOfParticle& op) {
    return thrust::make_transform_iterator(thrust::make_counting_iterator<std::uint32_t>(0), op);
}

}  // namespace

void make_sort_keys(const std::uint32_t* cell, const std::uint32_t* id, std::uint64_t* keys, std::uint32_t* order,
                    std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    make_sort_keys_kernel<<<blocks_for(n), block_size, 0, s>>>(cell, id, keys, order, n);
    SPH_CUDA_CHECK_LAUNCH();
}

void gather_sorted(const std::uint64_t* keys, const std::uint32_t* order, SortedArrays in, SortedArrays out,
                   std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    gather_sorted_kernel<<<blocks_for(n), block_size, 0, s>>>(keys, order, in, out, cell, id, n);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_cell_start(const std::uint32_t* sorted_cell, std::uint32_t n, std::uint32_t cell_count,
                      std::uint32_t* cell_start, cudaStream_t s) {
    // cell_start[c] = first sorted particle whose cell is >= c, for c = 0 .. cell_count.
    thrust::lower_bound(thrust::cuda::par_nosync.on(s), sorted_cell, sorted_cell + n,
                        thrust::make_counting_iterator<std::uint32_t>(0),
                        thrust::make_counting_iterator<std::uint32_t>(cell_count + 1), cell_start);
    SPH_CUDA_CHECK_LAUNCH();
}

void build_fluid_begin(const real4* sorted_velrho, const std::uint32_t* sorted_cell, const std::uint32_t* cell_start,
                       std::uint32_t n, std::uint32_t cell_count, std::uint32_t* fluid_begin, cudaStream_t s) {
    fluid_begin_init_kernel<<<blocks_for(cell_count + 1), block_size, 0, s>>>(cell_start, fluid_begin, cell_count);
    SPH_CUDA_CHECK_LAUNCH();
    if (n == 0) return;
    fluid_begin_mark_kernel<<<blocks_for(n), block_size, 0, s>>>(sorted_velrho, sorted_cell, fluid_begin, n, cell_count);
    SPH_CUDA_CHECK_LAUNCH();
}

void mark_ghosts(const std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, std::uint32_t begin, std::uint32_t end,
                 std::uint32_t out_of_domain, cudaStream_t s) {
    if (n == 0) return;
    mark_ghosts_kernel<<<blocks_for(n), block_size, 0, s>>>(cell, id, n, begin, end, out_of_domain);
    SPH_CUDA_CHECK_LAUNCH();
}

void clamp_cell_starts(std::uint32_t* cell_start, std::uint32_t* fluid_begin, std::uint32_t cell_count,
                       std::uint32_t lo, std::uint32_t hi, cudaStream_t s) {
    clamp_cell_starts_kernel<<<blocks_for(cell_count + 1), block_size, 0, s>>>(cell_start, fluid_begin, cell_count, lo, hi);
    SPH_CUDA_CHECK_LAUNCH();
}

ReceivedCount append_received_in(CarriedArrays from, std::uint32_t m, CarriedArrays to, std::uint32_t n,
                                 std::uint32_t begin, std::uint32_t end, std::uint32_t owned_begin,
                                 std::uint32_t owned_end, cudaStream_t s) {
    if (m == 0) return {};
    auto zip = [](const CarriedArrays& a, std::uint32_t at) {
        return thrust::make_zip_iterator(thrust::make_tuple(a.pos + at, a.velrho + at, a.velrho_prev + at, a.cell + at,
                                                            a.id + at));
    };
    const auto policy = thrust::cuda::par.on(s);
    const auto last = thrust::copy_if(policy, zip(from, 0), zip(from, m), from.cell, zip(to, n), CellIn{begin, end});
    SPH_CUDA_CHECK_LAUNCH();
    ReceivedCount c;
    c.kept = std::size_t(last - zip(to, n));
    c.owned = std::size_t(thrust::count_if(policy, from.cell, from.cell + m, CellIn{owned_begin, owned_end}));
    SPH_CUDA_CHECK_LAUNCH();
    return c;
}

// SPH_FORCE_LOOP=per-thread in the environment runs forces_kernel where the policy compacts,
// so that one build times both loops in one lease (bench/FORCE_LOOP_NOTES.md).
bool per_thread_loop_forced() {
    static const bool forced = [] {
        const char* v = std::getenv("SPH_FORCE_LOOP");
        return v != nullptr && std::string(v) == "per-thread";
    }();
    return forced;
}

void compute_forces(const SubdomainConfig& cfg, const ForceInputs& in, real4* force, ActiveRange range,
                    std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    dispatch_physics(cfg.kernel, cfg.diffusion, cfg.search, [&](auto k, auto srch, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        using Search = typename decltype(srch)::type;
        constexpr bool Diffusion = decltype(diffusion)::value;
        using Policy = ForceLoopPolicy;
        if constexpr (Policy::template compacted<Search>) {
            if (!(Search::merge && in.grid.periodic_z) && !per_thread_loop_forced()) {
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

// SPH_LIST_BUILD=per-lane in the environment builds the lists lane by lane (build_lists_kernel)
// where the policy walks in step, to time both on one build.
bool per_lane_list_build_forced() {
    static const bool forced = [] {
        const char* v = std::getenv("SPH_LIST_BUILD");
        return v != nullptr && std::string(v) == "per-lane";
    }();
    return forced;
}

bool lists_take_cell_offsets(const SubdomainConfig& cfg, std::uint32_t n) {
    static const bool plain = [] {
        const char* v = std::getenv("SPH_LIST_ENTRIES");
        return v != nullptr && std::string(v) == "plain";
    }();
    return !plain && !cfg.grid.any_periodic() && ListEntry::fits(n, cfg.search.cells_per_support);
}

template <class Search, bool CellOffsets>
void launch_list_build(const ForceInputs& in, real reach2, std::uint32_t* index, std::uint32_t* count,
                       std::uint32_t stride, std::uint32_t capacity, ActiveRange range, std::uint32_t n, cudaStream_t s) {
    const bool in_step = ListedLoopPolicy::build_in_step && !per_lane_list_build_forced();
    // One stencil per warp on open grids (cuda_warp_stencil_build.cuh); the lanes' own
    // stencils in step across periodic faces.
    if (in_step && !in.grid.any_periodic())
        build_lists_warp_stencil_kernel<Search, CellOffsets, block_size, list_stage_rows>
            <<<blocks_for(n), block_size, 0, s>>>(in, reach2, index, count, stride, capacity, range.begin, range.end);
    else if (in_step && !(Search::merge && in.grid.periodic_z))
        build_lists_in_step_kernel<Search, CellOffsets>
            <<<blocks_for(n), block_size, 0, s>>>(in, reach2, index, count, stride, capacity, range);
    else
        build_lists_kernel<Search, CellOffsets>
            <<<blocks_for(n), block_size, 0, s>>>(in, reach2, index, count, stride, capacity, range);
}

void build_neighbour_lists(const SubdomainConfig& cfg, const ForceInputs& in, real reach2, std::uint32_t* index,
                           std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity, bool cell_offsets,
                           ActiveRange range, std::uint32_t n, cudaStream_t s) {
    SPH_CUDA_CHECK(cudaMemsetAsync(count, 0, std::size_t(n) * sizeof(std::uint32_t), s));
    if (n == 0) return;
    dispatch_search(cfg.search, [&](auto srch) {
        using Search = typename decltype(srch)::type;
        if constexpr (Search::n <= ListEntry::reach_cells) {
            if (cell_offsets) {
                launch_list_build<Search, true>(in, reach2, index, count, stride, capacity, range, n, s);
                return;
            }
        }
        if (cell_offsets) throw RunError("lists with cell offsets need a stencil of at most 3 cells a side");
        launch_list_build<Search, false>(in, reach2, index, count, stride, capacity, range, n, s);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

std::size_t longest_list_temp_bytes(std::uint32_t n) {
    std::size_t bytes = 0;
    SPH_CUDA_CHECK(cub::DeviceReduce::Max(nullptr, bytes, static_cast<const std::uint32_t*>(nullptr),
                                          static_cast<std::uint32_t*>(nullptr), n));
    return bytes;
}

std::uint32_t longest_list(const std::uint32_t* count, std::uint32_t n, void* temp, std::size_t temp_bytes,
                           std::uint32_t* out, cudaStream_t s) {
    SPH_CUDA_CHECK(cub::DeviceReduce::Max(temp, temp_bytes, count, out, n, s));
    std::uint32_t longest = 0;
    SPH_CUDA_CHECK(cudaMemcpyAsync(&longest, out, sizeof longest, cudaMemcpyDeviceToHost, s));
    SPH_CUDA_CHECK(cudaStreamSynchronize(s));
    return longest;
}

// SPH_LISTED_POLICY=no-lookahead or =split-loads in the environment runs a variant of the
// listed loop's policy (cuda_launch_policy.cuh), to time it beside the policy on one build.
int listed_policy_variant() {
    static const int variant = [] {
        const char* v = std::getenv("SPH_LISTED_POLICY");
        const std::string name = v != nullptr ? v : "";
        return name == "no-lookahead" ? 1 : name == "split-loads" ? 2 : 0;
    }();
    return variant;
}

template <class Policy>
void launch_forces_listed(const SubdomainConfig& cfg, const ForceInputs& in, const NeighbourList& list, real4* force,
                          ActiveRange range, std::uint32_t n, cudaStream_t s) {
    dispatch_kernel(cfg.kernel, cfg.diffusion, [&](auto k, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        forces_listed_kernel<Kernel, decltype(diffusion)::value, Policy>
            <<<blocks_for<Policy::block_size>(n), Policy::block_size, 0, s>>>(in, list, cfg.params, force, range);
    });
}

template <class Policy>
void launch_forces_listed_layout(const SubdomainConfig& cfg, const ForceInputs& in, const NeighbourList& list,
                                 real4* force, ActiveRange range, std::uint32_t n, cudaStream_t s) {
    if (list.cell_offsets) launch_forces_listed<WithEntryOffsets<Policy>>(cfg, in, list, force, range, n, s);
    else launch_forces_listed<Policy>(cfg, in, list, force, range, n, s);
}

void compute_forces_listed(const SubdomainConfig& cfg, const ForceInputs& in, const NeighbourList& list, real4* force,
                           ActiveRange range, std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    if (list.cell_offsets && (in.grid.any_periodic() || in.build_frame == nullptr))
        throw RunError("a list with cell offsets needs an open grid and the positions of its rebuild");
    switch (listed_policy_variant()) {
    case 1: launch_forces_listed_layout<ListedLoopNoLookahead>(cfg, in, list, force, range, n, s); break;
    case 2: launch_forces_listed_layout<ListedLoopSplitLoads>(cfg, in, list, force, range, n, s); break;
    default: launch_forces_listed_layout<ListedLoopPolicy>(cfg, in, list, force, range, n, s);
    }
    SPH_CUDA_CHECK_LAUNCH();
}

void advance(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, const KeptCells& kept,
             const real4* force, const real4* grad_c, const TimeStep& step, const SubdomainConfig& cfg,
             ActiveRange range, std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    if (cfg.integrate_boundary)
        advance_kernel<true><<<blocks_for(n), block_size, 0, s>>>(pos, velrho, velrho_prev, cell, kept, force, grad_c,
                                                                   step, cfg.grid, cfg.params, range);
    else
        advance_kernel<false><<<blocks_for(n), block_size, 0, s>>>(pos, velrho, velrho_prev, cell, kept, force, grad_c,
                                                                    step, cfg.grid, cfg.params, range);
    SPH_CUDA_CHECK_LAUNCH();
}

void fill_cell_coords(const std::uint32_t* cell, const real4* pos, const KeptCells& kept, const GridView& g,
                      std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    cell_coords_kernel<<<blocks_for(n), block_size, 0, s>>>(cell, pos, kept, g, n);
    SPH_CUDA_CHECK_LAUNCH();
}

std::size_t reduce_stats_temp_bytes(std::uint32_t n) {
    std::size_t bytes = 0;
    SPH_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, stats_iterator(StatsOfParticle{}),
                                             static_cast<StepStats*>(nullptr), n, MergeStats{}, StepStats{}));
    return bytes;
}

void reduce_stats(const real4* velrho, const real4* velrho_prev, const real4* force, const std::uint32_t* id,
                  ActiveRange range, const TimeStep& step, const PhysicsParams& p, const StatsLimits& lim,
                  std::uint32_t n, void* temp, std::size_t temp_bytes, StepStats* out, cudaStream_t s) {
    const StatsOfParticle op{velrho, velrho_prev, force, id, range, step, p, lim};
    SPH_CUDA_CHECK(cub::DeviceReduce::Reduce(temp, temp_bytes, stats_iterator(op), out, n, MergeStats{}, StepStats{}, s));
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
