// CUDA kernels: thin wrappers that run the shared per-particle functions, one thread per
// particle, plus the CCCL calls that build cell ranges and reductions. Launch choices (block
// sizes, the force loop's neighbour buffer) come from cuda_launch_policy.cuh.
#include <cub/block/block_reduce.cuh>
#include <cub/device/device_reduce.cuh>
#include <thrust/binary_search.h>
#include <thrust/execution_policy.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>

#include <cstdlib>
#include <string>


#include "backend/cuda_drivers.cuh"
#include "backend/cuda_check.cuh"
#include "backend/cuda_launch_policy.cuh"
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

// The plain force loop: one thread per particle visiting its stencil (particle_force), walls
// only the fluid of each cell; the pair body runs inside the search, at the lanes that have a
// neighbour at that candidate (about 15 of 32). Kept for SPH_FORCE_LOOP=per-thread.
template <class Kernel, class Search, bool Diffusion, class Policy>
__global__ void __launch_bounds__(Policy::block_size)
    forces_kernel(ForceInputs in, PhysicsParams p, real4* __restrict__ force, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * Policy::block_size + threadIdx.x;
    if (i >= *range.end) return;
    const Kernel kernel(p.h);
    force[i] = particle_force<Kernel, Search, Diffusion>(i, in, p, kernel);
}

// A neighbour's cell offset (each component in [-4, 4], cells per support at most 4) in
// 4 bits a component.
__device__ __forceinline__ std::uint16_t pack_offset(int dx, int dy, int dz) {
    return std::uint16_t((dx + 8) | ((dy + 8) << 4) | ((dz + 8) << 8));
}
__device__ __forceinline__ int offset_x(unsigned o) { return int(o & 15u) - 8; }
__device__ __forceinline__ int offset_y(unsigned o) { return int((o >> 4) & 15u) - 8; }
__device__ __forceinline__ int offset_z(unsigned o) { return int(o >> 8) - 8; }

// The force loop with the pair body deferred: the same per-thread search (visit_ranges, in
// visit()'s order), but a candidate inside the support only goes into the thread's column of
// a shared buffer. After each stencil range the lanes that are together there vote, and when
// one has half a buffer they all run the pair body over their buffers: the body runs on most
// lanes at once instead of at those with a neighbour at the same candidate. Lanes of one cell
// walk the same ranges, so they meet after each. Every lane drains only its own buffer, so the
// result does not depend on which lanes vote together; a full buffer drains at once. Sums
// come out in visit()'s order, as in forces_kernel.
template <class Kernel, class Search, bool Diffusion, class Policy>
__global__ void __launch_bounds__(Policy::block_size)
    forces_deferred_kernel(ForceInputs in, PhysicsParams p, real4* __restrict__ force, ActiveRange range) {
    __shared__ std::uint32_t slot_j[Policy::chunk][Policy::block_size];
    __shared__ std::uint16_t slot_offset[Policy::chunk][Policy::block_size];
    const std::uint32_t i = *range.begin + blockIdx.x * Policy::block_size + threadIdx.x;
    if (i >= *range.end) return;
    const Kernel kernel(p.h);
    PairSums<Kernel, Diffusion> sums(i, in, p, kernel);
    const real3 cs = in.grid.cell_size;
    const int3v c = in.grid.decode(in.cell[i]);
    int count = 0;
    auto drain = [&] {
        for (int k = 0; k < count; ++k) {
            const std::uint32_t j = slot_j[k][threadIdx.x];
            const unsigned o = slot_offset[k][threadIdx.x];
            const real3 rij = separation(sums.pos_i, in.pos[j], offset_x(o), offset_y(o), offset_z(o), cs);
            sums.add(j, rij, dot(rij, rij));
        }
        count = 0;
    };
    auto take = [&](const CellRange& r) {
        for (std::uint32_t j = r.begin; j < r.end; ++j) {
            const int dz = r.merged ? int(in.cell[j]) - r.z_ref : r.dz;
            const real3 rij = separation(sums.pos_i, in.pos[j], r.dx, r.dy, dz, cs);
            const real r2 = dot(rij, rij);
            if (r2 < p.support2 && r2 > real(1e-18) * p.support2) {
                slot_j[count][threadIdx.x] = j;
                slot_offset[count][threadIdx.x] = pack_offset(r.dx, r.dy, dz);
                if (++count == Policy::chunk) drain();
            }
        }
        if (__any_sync(__activemask(), count >= Policy::drain_at)) drain();
    };
    if (sums.fluid_i) Search::template visit_ranges<false>(in.grid, in.cell_start, in.cell_start, c, take);
    else Search::template visit_ranges<true>(in.grid, in.cell_start, in.fluid_begin, c, take);
    drain();
    force[i] = sums.result();
}

// SPH_FORCE_LOOP=per-thread selects the plain loop (read once): a switch for timing both
// loops on one build, not a setting of runs.
bool plain_force_loop_requested() {
    static const bool requested = [] {
        const char* v = std::getenv("SPH_FORCE_LOOP");
        return v != nullptr && std::string(v) == "per-thread";
    }();
    return requested;
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
__global__ void __launch_bounds__(block_size) build_lists_kernel(ForceInputs in, real reach2, std::uint32_t* index,
                                                                 std::uint32_t* count, std::uint32_t stride,
                                                                 std::uint32_t capacity, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    count[i] = build_particle_list<Search>(i, in, reach2, index, stride, capacity);
}

template <class Kernel, bool Diffusion>
__global__ void __launch_bounds__(block_size) forces_listed_kernel(ForceInputs in, NeighbourList list, PhysicsParams p,
                                                                   real4* __restrict__ force,
                                                                   ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    if (in.cell[i] >= in.grid.out_of_domain()) {  // left the domain since the last rebuild
        force[i] = real4{0, 0, 0, 0};
        return;
    }
    const Kernel kernel(p.h);
    force[i] = particle_force_listed<Kernel, Diffusion>(i, in, list, p, kernel);
}

template <bool IntegrateBoundary>
__global__ void advance_kernel(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, const real4* force,
                               const real4* grad_c, TimeStep step, GridView g, PhysicsParams p, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    particle_advance<IntegrateBoundary>(i, pos, velrho, velrho_prev, cell, force, grad_c, step, g, p);
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

void compute_forces(const SubdomainConfig& cfg, const ForceInputs& in, real4* force, ActiveRange range,
                    std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    // The deferred loop needs fluid_begin (walls) and the cell offsets it packs in 4 bits.
    const bool deferred = in.fluid_begin != nullptr && !plain_force_loop_requested();
    dispatch_physics(cfg.kernel, cfg.diffusion, cfg.search, [&](auto k, auto srch, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        using Search = typename decltype(srch)::type;
        constexpr bool Diffusion = decltype(diffusion)::value;
        using Policy = ForceLoopPolicy;
        if (deferred)
            forces_deferred_kernel<Kernel, Search, Diffusion, Policy>
                <<<blocks_for<Policy::block_size>(n), Policy::block_size, 0, s>>>(in, cfg.params, force, range);
        else
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

void build_neighbour_lists(const SubdomainConfig& cfg, const ForceInputs& in, real reach2, std::uint32_t* index,
                           std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity,
                           ActiveRange range, std::uint32_t n, cudaStream_t s) {
    SPH_CUDA_CHECK(cudaMemsetAsync(count, 0, std::size_t(n) * sizeof(std::uint32_t), s));
    if (n == 0) return;
    dispatch_search(cfg.search, [&](auto srch) {
        using Search = typename decltype(srch)::type;
        build_lists_kernel<Search><<<blocks_for(n), block_size, 0, s>>>(in, reach2, index, count, stride, capacity,
                                                                        range);
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

void compute_forces_listed(const SubdomainConfig& cfg, const ForceInputs& in, const NeighbourList& list, real4* force,
                           ActiveRange range, std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    dispatch_kernel(cfg.kernel, cfg.diffusion, [&](auto k, auto diffusion) {
        using Kernel = typename decltype(k)::type;
        forces_listed_kernel<Kernel, decltype(diffusion)::value>
            <<<blocks_for(n), block_size, 0, s>>>(in, list, cfg.params, force, range);
    });
    SPH_CUDA_CHECK_LAUNCH();
}

void advance(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, const real4* force,
             const real4* grad_c, const TimeStep& step, const SubdomainConfig& cfg, ActiveRange range, std::uint32_t n,
             cudaStream_t s) {
    if (n == 0) return;
    if (cfg.integrate_boundary)
        advance_kernel<true><<<blocks_for(n), block_size, 0, s>>>(pos, velrho, velrho_prev, cell, force, grad_c, step,
                                                                   cfg.grid, cfg.params, range);
    else
        advance_kernel<false><<<blocks_for(n), block_size, 0, s>>>(pos, velrho, velrho_prev, cell, force, grad_c,
                                                                    step, cfg.grid, cfg.params, range);
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
