// Verlet lists: the rebuild's kernels (each particle's cell coordinates and build frame, the
// lists built lane by lane or with a warp's lanes in step), the longest list (CUB), and the
// listed force loop. Launch choices come from cuda_launch_policy.cuh, the variants from
// SubdomainConfig::variants.
#include <cub/device/device_reduce.cuh>

#include <algorithm>

#include "backend/cuda_check.cuh"
#include "backend/cuda_neighbour_lists.cuh"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph::gpu {
namespace {

constexpr int block_size = ElementwisePolicy::block_size;

template <class Search, bool CellOffsets>
__global__ void __launch_bounds__(block_size) build_lists_kernel(ForceInputs in, real reach2, std::uint32_t* index,
                                                                 std::uint32_t* count, std::uint32_t stride,
                                                                 std::uint32_t capacity, ActiveRange range) {
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= *range.end) return;
    count[i] = build_particle_list<Search, CellOffsets>(i, in, reach2, index, stride, capacity);
}

// The same lists, built with a warp's lanes walking their stencils in step
// (visit_ranges_in_step, as forces_compacted_kernel), each lane keeping its newest chunk of
// list_chunk entries in registers and storing it whole, one aligned 16-byte piece, as soon as
// it is full. (Before change 17 a warp staged 32 rows in shared memory and stored the rows all
// its lanes had filled; a lane more than 32 rows ahead of the warp's shortest list stored 4
// bytes at a time: in a flowing dam break ~37% of the entries, 6.5 sectors a store request and
// 2.4 GB of DRAM writes for a 1 GB list, and the 16 KB of ring a block left the L1 ~20 KB.)
// The same candidates in the same order (the StepwiseRanges test), so the same lists; not for
// merged runs across a periodic z face, which come in pieces (the driver keeps the other
// kernel there). CellOffsets stores ListEntry codes, as build_particle_list.
constexpr std::uint32_t list_test_chunk = 8;  // a half cell holds ~7 particles on the dam break (cells of reach / 2)

template <class Search, bool CellOffsets>
__global__ void __launch_bounds__(block_size)
    build_lists_in_step_kernel(ForceInputs in, real reach2, std::uint32_t* index, std::uint32_t* count,
                               std::uint32_t stride, std::uint32_t capacity, ActiveRange range) {
    static_assert(list_chunk == 4, "a chunk's entries are set by a chain of selects");
    const std::uint32_t end = *range.end;
    const std::uint32_t i = *range.begin + blockIdx.x * blockDim.x + threadIdx.x;
    const std::uint32_t first = i - threadIdx.x % 32;
    if (first >= end) return;  // the whole warp is past the end
    const bool valid = i < end;
    const std::uint32_t me = valid ? i : end - 1;  // a lane past the end walks nothing
    const real4 pos_i = in.pos[me];
    const bool fluid_i = !is_boundary(in.velrho[me]);
    const GridView& g = in.grid;
    // A wall lists fluid only (build_particle_list): a cell's range starts at its fluid, a
    // merged run holds each cell's walls, which the test drops.
    const bool walls_out = Search::merge && !fluid_i;
    ListChunk* chunks = reinterpret_cast<ListChunk*>(index);
    ListChunk newest{};      // entries [n - n % list_chunk, n) of this lane's list
    std::uint32_t n = 0;     // this lane's entries so far
    Search::visit_ranges_in_step(
        g, in.cell_start, in.fluid_begin, g.decode(in.cell[me]), valid, !fluid_i,
        [&](std::uint32_t b, std::uint32_t e, int dx, int dy, typename Search::RangeZ z) {
            // Two passes per list_test_chunk candidates: their positions loaded together and
            // tested into a mask, then the entries of its bits. Tested and stored one by one,
            // a lane waited on each position in turn (the stores kept the next load from being
            // issued early): long-scoreboard stalls were 73% of the kernel's cycles (change 16).
            for (std::uint32_t j0 = b; j0 < e; j0 += list_test_chunk) {
                real4 pj[list_test_chunk];
#pragma unroll
                for (std::uint32_t k = 0; k < list_test_chunk; ++k)
                    if (j0 + k < e) pj[k] = in.pos[j0 + k];
                std::uint32_t hits = 0;
#pragma unroll
                for (std::uint32_t k = 0; k < list_test_chunk; ++k) {
                    if (j0 + k >= e) break;
                    const real3 rij = separation(pos_i, pj[k], dx, dy, z.of(in.cell, j0 + k), g.cell_size);
                    if (j0 + k != me && dot(rij, rij) < reach2) hits |= 1u << k;
                }
                for (; hits != 0; hits &= hits - 1) {
                    const std::uint32_t j = j0 + std::uint32_t(lowest_set_bit(hits));
                    if (walls_out && is_boundary(in.velrho[j])) continue;
                    const std::uint32_t entry = CellOffsets ? ListEntry::encode(j, dx, dy, z.of(in.cell, j)) : j;
                    const std::uint32_t slot = n % list_chunk;
                    newest.e[0] = slot == 0 ? entry : newest.e[0];
                    newest.e[1] = slot == 1 ? entry : newest.e[1];
                    newest.e[2] = slot == 2 ? entry : newest.e[2];
                    newest.e[3] = slot == 3 ? entry : newest.e[3];
                    if (slot == list_chunk - 1 && n < capacity) chunks[std::size_t(n / list_chunk) * stride + i] = newest;
                    ++n;
                }
            }
        });
    if (valid && n % list_chunk != 0 && n < capacity) chunks[std::size_t(n / list_chunk) * stride + i] = newest;
    if (valid) count[i] = n;
}

// The same lists, built by one warp per cell (change 22). The particles of a cell share their
// stencil: its (2n+1)^2 columns, each one contiguous range of the sorted particles on an open z
// (a column's cells are consecutive), in the order visit_ranges() reads them. The warp's lanes
// take 32 consecutive candidates of the columns laid end to end, each loaded once for all of
// the cell's particles; then, particle by particle, every lane tests its candidate and a
// ballot gives each kept entry its slot (the particle's count so far plus the kept lanes below
// it), so a particle's entries come in the stencil's order, as the other builds store them:
// the same lists. A wall lists fluid only: in each cell the walls come first (the sort), so
// dropping wall candidates leaves the fluid of every cell in the same order as the ranges
// from fluid_begin. The lane-per-particle builds ran at ~19 of 32 threads active (ranges of
// different lengths, hits stored one lane at a time) and ~1,370 warp instructions a particle
// (change 17's ncu); here the tests run on full warps and each candidate's loads serve every
// particle of its cell. Before the per-particle tests, a candidate farther than the reach from
// the box of the cell's particles (which no particle of it can then list) leaves, and so does a
// wall for a cell of walls; the rest wait in a ring in shared memory, in order, until 32 are
// tested together, so that the lanes stay full. Stencils of at most 32 columns (n <= 2); not for a periodic z (its
// columns wrap, so they are not one range each), where the driver keeps the in-step build.
template <class Search, bool CellOffsets>
__global__ void __launch_bounds__(block_size)
    build_lists_by_cell_kernel(ForceInputs in, real reach2, std::uint32_t* index, std::uint32_t* count,
                               std::uint32_t stride, std::uint32_t capacity, ActiveRange range) {
    constexpr int N = Search::n;
    constexpr int side = 2 * N + 1;
    static_assert(side * side <= 32, "one lane a stencil column");
    const GridView& g = in.grid;
    const std::uint32_t cell = blockIdx.x * (blockDim.x / 32) + threadIdx.x / 32;  // no 32-bit overflow of the thread index past 2^27 cells
    const int lane = int(threadIdx.x % 32);
    if (cell >= g.cell_count()) return;  // the whole warp
    const std::uint32_t first = max(in.cell_start[cell], *range.begin);
    const std::uint32_t last = min(in.cell_start[cell + 1], *range.end);
    if (first >= last) return;  // an empty cell, or none of its particles is built here
    const int3v c = g.decode(cell);
    // Lane k < side^2 holds stencil column k = (dx, dy), in visit_ranges()' order (dx outer):
    // its candidates [b, e) and the cell index that gives a candidate's dz (cell[j] - ref).
    int dx = lane / side - N, dy = lane % side - N;
    std::uint32_t b = 0, e = 0;
    int ref = 0;
    if (lane < side * side) {
        int x = c.x + dx, y = c.y + dy;
        bool ok = true;
        if (x < 0 || x >= g.nx) {
            if (g.periodic_x) x = wrap_index(x, g.nx);
            else ok = false;
        }
        if (y < 0 || y >= g.ny) {
            if (g.periodic_y) y = wrap_index(y, g.ny);
            else ok = false;
        }
        if (ok) {
            const std::uint32_t column = g.encode(x, y, 0);
            const int z0 = c.z - N < 0 ? 0 : c.z - N, z1 = c.z + N >= g.nz ? g.nz - 1 : c.z + N;
            b = in.cell_start[column + z0];
            e = in.cell_start[column + z1 + 1];
            ref = int(column) + c.z;
        }
    }
    // The columns end to end: lane k's exclusive prefix of the lengths (the lanes past the
    // stencil hold empty columns at the total, which no candidate index reaches).
    std::uint32_t prefix = e - b;
    for (int d = 1; d < 32; d *= 2) {
        const std::uint32_t below = __shfl_up_sync(full_warp, prefix, d);
        if (lane >= d) prefix += below;
    }
    const std::uint32_t total = __shfl_sync(full_warp, prefix, 31);
    const std::uint32_t before = prefix - (e - b);
    const std::uint32_t fluid_first = in.fluid_begin[cell];
    const bool walls_here = first < fluid_first;  // the cell's walls come first
    const std::uint32_t below_me = (1u << lane) - 1;
    const std::size_t chunk_stride = std::size_t(stride) * sizeof(ListChunk);  // bytes from a row's chunk c to c + 1
    // Each warp's candidates that passed the box test, in order, until 32 of them are tested
    // together: a ring of 64 (a round adds at most 32 to fewer than 32 waiting).
    constexpr int ring = 64;
    __shared__ real ring_x[block_size / 32][ring], ring_y[block_size / 32][ring], ring_z[block_size / 32][ring];
    __shared__ std::uint32_t ring_j[block_size / 32][ring], ring_entry[block_size / 32][ring], ring_d[block_size / 32][ring];
    const int w = int(threadIdx.x / 32);
    const real reach2_box = reach2 * real(1.0001);  // room for the rounding of j's offset from i's cell
    for (std::uint32_t group = first; group < last; group += 32) {
        const std::uint32_t members = min(last - group, 32u);
        // The box of the group's positions (offsets in their cell) and whether all are walls.
        real3 lo{real(1e30), real(1e30), real(1e30)}, hi{-real(1e30), -real(1e30), -real(1e30)};
        if (std::uint32_t(lane) < members) {
            const real4 p = in.pos[group + std::uint32_t(lane)];
            lo = hi = make3(p.x, p.y, p.z);
        }
        for (int d = 16; d > 0; d /= 2) {
            lo.x = fmin(lo.x, __shfl_xor_sync(full_warp, lo.x, d));
            lo.y = fmin(lo.y, __shfl_xor_sync(full_warp, lo.y, d));
            lo.z = fmin(lo.z, __shfl_xor_sync(full_warp, lo.z, d));
            hi.x = fmax(hi.x, __shfl_xor_sync(full_warp, hi.x, d));
            hi.y = fmax(hi.y, __shfl_xor_sync(full_warp, hi.y, d));
            hi.z = fmax(hi.z, __shfl_xor_sync(full_warp, hi.z, d));
        }
        const bool all_walls = group + members <= fluid_first;
        std::uint32_t n = 0;  // lane q: the entries of particle group + q so far
        // Tests the `avail` ring entries from `head` against each particle of the group.
        const auto test_ring = [&](std::uint32_t head, std::uint32_t avail) {
            const std::uint32_t r = (head + std::uint32_t(lane)) % ring;
            const bool candidate = std::uint32_t(lane) < avail;
            const std::uint32_t j = ring_j[w][r], entry = ring_entry[w][r], packed = ring_d[w][r];
            const real4 pj{ring_x[w][r], ring_y[w][r], ring_z[w][r], 0};
            const int jdx = int(packed & 15) - 8, jdy = int(packed >> 4 & 15) - 8, jdz = int(packed >> 8 & 15) - 8;
            const bool wall_j = (packed >> 12) != 0;
#pragma unroll 4
            for (std::uint32_t q = 0; q < members; ++q) {
                const std::uint32_t i = group + q;
                const real3 rij = separation(in.pos[i], pj, jdx, jdy, jdz, g.cell_size);
                // One test of every condition, no short cuts: a branch per particle otherwise.
                const bool keep = candidate & (j != i) & (dot(rij, rij) < reach2) & !(wall_j & (i < fluid_first));
                const std::uint32_t kept = __ballot_sync(full_warp, keep);
                const std::uint32_t slot = __shfl_sync(full_warp, n, int(q)) + std::uint32_t(__popc(kept & below_me));
                // list_slot(slot, i, stride) as a byte address: i's chunk 0 (the same on every
                // lane) plus slot / 4 chunk strides, one wide multiply-add.
                char* row = reinterpret_cast<char*>(index) + std::size_t(i) * sizeof(ListChunk);
                std::uint32_t* at = reinterpret_cast<std::uint32_t*>(row + std::size_t(slot / list_chunk) * chunk_stride) +
                                    slot % list_chunk;
                if (keep & (slot < capacity)) *at = entry;
                if (std::uint32_t(lane) == q) n += std::uint32_t(__popc(kept));
            }
        };
        std::uint32_t head = 0, queued = 0;
        for (std::uint32_t t0 = 0; t0 < total; t0 += 32) {
            const std::uint32_t t = t0 + std::uint32_t(lane);
            // The column holding candidate t: the last k whose prefix is at most t.
            int k = 0;
#pragma unroll
            for (int step = 16; step > 0; step /= 2) {
                const std::uint32_t at = __shfl_sync(full_warp, before, k + step);
                if (at <= t) k += step;
            }
            const bool candidate = t < total;
            // Every lane takes part in every shuffle (a shuffle under the condition would not).
            const std::uint32_t column_b = __shfl_sync(full_warp, b, k), column_before = __shfl_sync(full_warp, before, k);
            const std::uint32_t j = candidate ? column_b + (t - column_before) : first;
            const int jdx = __shfl_sync(full_warp, dx, k), jdy = __shfl_sync(full_warp, dy, k);
            const int jdz = int(in.cell[j]) - __shfl_sync(full_warp, ref, k);
            const real4 pj = in.pos[j];
            const bool wall_j = walls_here && is_boundary(in.velrho[j]);
            // Candidates farther than the reach from the group's box reach none of it: they
            // leave before the per-particle tests (about a third of a stencil of half cells).
            const real gx = fmax(fmax(lo.x - (pj.x + jdx * g.cell_size.x), (pj.x + jdx * g.cell_size.x) - hi.x), real(0));
            const real gy = fmax(fmax(lo.y - (pj.y + jdy * g.cell_size.y), (pj.y + jdy * g.cell_size.y) - hi.y), real(0));
            const real gz = fmax(fmax(lo.z - (pj.z + jdz * g.cell_size.z), (pj.z + jdz * g.cell_size.z) - hi.z), real(0));
            const bool near = candidate & (gx * gx + gy * gy + gz * gz <= reach2_box) & !(wall_j & all_walls);
            const std::uint32_t passed = __ballot_sync(full_warp, near);
            if (near) {
                const std::uint32_t r = (head + queued + std::uint32_t(__popc(passed & below_me))) % ring;
                ring_x[w][r] = pj.x;
                ring_y[w][r] = pj.y;
                ring_z[w][r] = pj.z;
                ring_j[w][r] = j;
                ring_entry[w][r] = CellOffsets ? ListEntry::encode(j, jdx, jdy, jdz) : j;
                ring_d[w][r] = std::uint32_t(jdx + 8) | std::uint32_t(jdy + 8) << 4 | std::uint32_t(jdz + 8) << 8 |
                               std::uint32_t(wall_j) << 12;
            }
            queued += std::uint32_t(__popc(passed));
            __syncwarp();
            if (queued >= 32) {
                test_ring(head, 32);
                head = (head + 32) % ring;
                queued -= 32;
                __syncwarp();  // the next round writes where this one read
            }
        }
        if (queued > 0) test_ring(head, queued);
        __syncwarp();
        if (std::uint32_t(lane) < members) count[group + std::uint32_t(lane)] = n;
    }
}

// The listed loop: one thread per particle over its stored list, cells read as coordinates.
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

}  // namespace

// list_entries = plain keeps the plain entries where cell offsets would fit: the layout of
// periodic grids, wide stencils and large subdomains, selectable to test it on any grid.
bool lists_take_cell_offsets(const SubdomainConfig& cfg, std::uint32_t n) {
    // The run's bound where it is known, so that every subdomain decides alike (a ghost
    // refresh copies the list frame between them).
    const std::size_t bound = std::max<std::size_t>(n, cfg.particles_in_run);
    return cfg.variants.list_entries == ListEntriesVariant::automatic && !cfg.grid.any_periodic() &&
           bound <= 0xffffffffu && ListEntry::fits(std::uint32_t(bound), cfg.search.cells_per_support);
}

// list_build = auto builds by cell (stencils of at most 32 columns on an open z), else with the
// lanes in step; in-step is that fallback, per-lane (build_lists_kernel) the build merged
// z-runs across a periodic z face need; each selectable to test it anywhere.
template <class Search, bool CellOffsets>
void launch_list_build(const SubdomainConfig& cfg, const ForceInputs& in, real reach2, std::uint32_t* index,
                       std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity, ActiveRange range,
                       std::uint32_t n, cudaStream_t s) {
    const ListBuildVariant v = cfg.variants.list_build;
    if constexpr ((2 * Search::n + 1) * (2 * Search::n + 1) <= 32) {
        if (v == ListBuildVariant::automatic && !in.grid.periodic_z) {
            const std::uint32_t warps_per_block = block_size / 32;
            const std::uint32_t blocks = (in.grid.cell_count() + warps_per_block - 1) / warps_per_block;
            build_lists_by_cell_kernel<Search, CellOffsets>
                <<<blocks, block_size, 0, s>>>(in, reach2, index, count, stride, capacity, range);
            return;
        }
    }
    const bool in_step = ListedLoopPolicy::build_in_step && v != ListBuildVariant::per_lane;
    if (in_step && !(Search::merge && in.grid.periodic_z))
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
                launch_list_build<Search, true>(cfg, in, reach2, index, count, stride, capacity, range, n, s);
                return;
            }
        }
        if (cell_offsets) throw RunError("lists with cell offsets need a stencil of at most 3 cells a side");
        launch_list_build<Search, false>(cfg, in, reach2, index, count, stride, capacity, range, n, s);
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
    launch_forces_listed_layout<ListedLoopPolicy>(cfg, in, list, force, range, n, s);
    SPH_CUDA_CHECK_LAUNCH();
}

void fill_cell_coords(const std::uint32_t* cell, const real4* pos, const KeptCells& kept, const GridView& g,
                      std::uint32_t n, cudaStream_t s) {
    if (n == 0) return;
    cell_coords_kernel<<<blocks_for(n), block_size, 0, s>>>(cell, pos, kept, g, n);
    SPH_CUDA_CHECK_LAUNCH();
}

}  // namespace sph::gpu
