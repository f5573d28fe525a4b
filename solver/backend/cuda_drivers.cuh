#pragma once
// Driver functions: the only way host code launches the CUDA kernels (HOOMD-blue's pattern).
// Each takes plain pointers and a stream, and checks its launch.
#include <cuda_runtime.h>

#include "backend/subdomain.hpp"

namespace sph::gpu {

// The particles a kernel works on, as device pointers into cell_start: [*begin, *end). Kernels
// are launched over all n particles and skip the rest (particles that left the domain, ghosts
// of other subdomains) without a host round trip.
struct ActiveRange {
    const std::uint32_t* begin;
    const std::uint32_t* end;
};

void make_sort_keys(const std::uint32_t* cell, const std::uint32_t* id, std::uint64_t* keys, std::uint32_t* order,
                    std::uint32_t n, cudaStream_t s);
// The real4 arrays a sort permutes: positions, velocity and density, the previous step's.
struct SortedArrays {
    real4* pos;
    real4* velrho;
    real4* velrho_prev;
};
void gather_sorted(const std::uint64_t* keys, const std::uint32_t* order, SortedArrays in, SortedArrays out,
                   std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, cudaStream_t s);
void build_cell_start(const std::uint32_t* sorted_cell, std::uint32_t n, std::uint32_t cell_count,
                      std::uint32_t* cell_start, cudaStream_t s);
// fluid_begin[c] = the first fluid particle of cell c, or cell_start[c + 1] when it has none
// (the sort puts each cell's boundary particles first).
void build_fluid_begin(const real4* sorted_velrho, const std::uint32_t* sorted_cell, const std::uint32_t* cell_start,
                       std::uint32_t n, std::uint32_t cell_count, std::uint32_t* fluid_begin, cudaStream_t s);
// Marks the particles of in-domain cells outside [begin, end) as ghosts (particle.hpp).
void mark_ghosts(const std::uint32_t* cell, std::uint32_t* id, std::uint32_t n, std::uint32_t begin, std::uint32_t end,
                 std::uint32_t out_of_domain, cudaStream_t s);
// After keeping the particles [lo, hi) of a sorted range (moved to the front): the cell
// ranges shifted down by lo, cells outside them empty (cell_start and fluid_begin).
void clamp_cell_starts(std::uint32_t* cell_start, std::uint32_t* fluid_begin, std::uint32_t cell_count,
                       std::uint32_t lo, std::uint32_t hi, cudaStream_t s);
// The five arrays of particles an exchange carries.
struct CarriedArrays {
    real4* pos;
    real4* velrho;
    real4* velrho_prev;
    std::uint32_t* cell;
    std::uint32_t* id;
};
// Appends the m particles of `from` whose cell lies in [begin, end) to `to` at index n, in
// their order; returns how many, and how many of them lie in [owned_begin, owned_end)
// (synchronises the stream).
ReceivedCount append_received_in(CarriedArrays from, std::uint32_t m, CarriedArrays to, std::uint32_t n,
                                 std::uint32_t begin, std::uint32_t end, std::uint32_t owned_begin,
                                 std::uint32_t owned_end, cudaStream_t s);
void compute_forces(const SubdomainConfig& cfg, const ForceInputs& in, real4* force, ActiveRange range,
                    std::uint32_t n, cudaStream_t s);
// Particle shifting's concentration gradient (cell search only).
void concentration_gradient(const SubdomainConfig& cfg, const ForceInputs& in, real4* grad_c, ActiveRange range,
                            std::uint32_t n, cudaStream_t s);
// Whether a subdomain of n particles stores its lists with cell offsets (ListEntry): open
// grids, stencils of at most ListEntry::reach_cells, fewer than 2^23 particles, and not
// SPH_LIST_ENTRIES=plain in the environment (which times the plain entries on one build).
bool lists_take_cell_offsets(const SubdomainConfig& cfg, std::uint32_t n);
// Writes each particle's list and count; returns nothing (the caller reduces the counts).
// cell_offsets writes ListEntry codes (searches of at most ListEntry::reach_cells a side).
void build_neighbour_lists(const SubdomainConfig& cfg, const ForceInputs& in, real reach2, std::uint32_t* index,
                           std::uint32_t* count, std::uint32_t stride, std::uint32_t capacity, bool cell_offsets,
                           ActiveRange range, std::uint32_t n, cudaStream_t s);
// The longest list, on the host (synchronises the stream).
std::uint32_t longest_list(const std::uint32_t* count, std::uint32_t n, void* temp, std::size_t temp_bytes,
                           std::uint32_t* out, cudaStream_t s);
std::size_t longest_list_temp_bytes(std::uint32_t n);
void compute_forces_listed(const SubdomainConfig& cfg, const ForceInputs& in, const NeighbourList& list, real4* force,
                           ActiveRange range, std::uint32_t n, cudaStream_t s);
// kept: what the listed loop reads of each particle's cell, kept up between rebuilds (KeptCells).
void advance(real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell, const KeptCells& kept,
             const real4* force, const real4* grad_c, const TimeStep& step, const SubdomainConfig& cfg,
             ActiveRange range, std::uint32_t n, cudaStream_t s);
// Each particle's cell as coordinates, from the linear cells (after a sort), and, where kept
// has a build frame, its position as the frame's start.
void fill_cell_coords(const std::uint32_t* cell, const real4* pos, const KeptCells& kept, const GridView& g,
                      std::uint32_t n, cudaStream_t s);
// Bytes of temporary storage reduce_stats needs for n particles.
std::size_t reduce_stats_temp_bytes(std::uint32_t n);
void reduce_stats(const real4* velrho, const real4* velrho_prev, const real4* force, const std::uint32_t* id,
                  ActiveRange range, const TimeStep& step, const PhysicsParams& p, const StatsLimits& lim, std::uint32_t n, void* temp,
                  std::size_t temp_bytes, StepStats* out, cudaStream_t s);
void count_work(const SubdomainConfig& cfg, const ForceInputs& in, ActiveRange range, std::uint32_t n,
                unsigned long long* counters3, cudaStream_t s);

}  // namespace sph::gpu
