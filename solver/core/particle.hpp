#pragma once
// How one particle is laid out in memory, and the accessors that hide the encoding.
//
//   pos    : x, y, z = offset of the particle inside its cell (0 <= offset < cell size),
//            w = P / rho^2 at the density the next force evaluation uses.
//            Keeping the offset relative to the cell (as GPUSPH and DualSPHysics do) means
//            float32 loses no accuracy far from the origin: the cell index carries the
//            coarse part exactly.
//   velrho : x, y, z = velocity, w = density, negated for boundary particles. The sign is
//            the particle type: the force loop learns the neighbour's type from a load it
//            makes anyway.
//   cell   : linear cell index in the subdomain grid (z fastest, then y, then x);
//            out_of_domain_cell(grid) for particles that left the domain.
//   id     : stable particle id; boundary particles have the lowest ids.
#include "core/types.hpp"

namespace sph {

SPH_HD real density(const real4& velrho) { return velrho.w < 0 ? -velrho.w : velrho.w; }
SPH_HD bool is_boundary(const real4& velrho) { return velrho.w < 0; }
SPH_HD real4 make_velrho(real3 v, real rho, bool boundary) {
    return {v.x, v.y, v.z, boundary ? -rho : rho};
}

// Ghost copies of a neighbour subdomain's particles carry this bit in their id: they sort
// after owned particles of the same cell and are never written out.
constexpr std::uint32_t ghost_id_flag = 0x80000000u;
SPH_HD bool is_ghost_id(std::uint32_t id) { return (id & ghost_id_flag) != 0; }
// A particle of an in-domain cell outside a subdomain's owned cells [begin, end) is a ghost.
SPH_HD std::uint32_t mark_ghost(std::uint32_t id, std::uint32_t cell, std::uint32_t begin, std::uint32_t end,
                                std::uint32_t out_of_domain) {
    const bool ghost = cell < out_of_domain && (cell < begin || cell >= end);
    return ghost ? id | ghost_id_flag : id & ~ghost_id_flag;
}

}  // namespace sph
