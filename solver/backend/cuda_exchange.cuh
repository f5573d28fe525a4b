#pragma once
// Drivers of what a decomposition asks of a subdomain's particles (cuda_exchange.cu): ghosts
// marked, a cell range kept, received particles appended.
#include <cuda_runtime.h>

#include "backend/cuda_launch.cuh"
#include "backend/subdomain.hpp"

namespace sph::gpu {

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

}  // namespace sph::gpu
