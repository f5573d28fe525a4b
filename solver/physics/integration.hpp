#pragma once
// Kick-drift-kick velocity Verlet, one force evaluation per step:
//   kick_drift: v += dt/2 a;  rho += dt/2 drho;  x += dt v   (then the particle changes cell
//               if its offset left the cell; P/rho^2 is refreshed for the next force loop)
//   forces at the new positions
//   kick:       v += dt/2 a;  rho += dt/2 drho
// A particle that drifts through a periodic face re-enters on the other side: its cell
// index wraps and its offset inside the cell is kept.
// Boundary particles only integrate density (dynamic boundary), floored at rho0 as in
// DualSPHysics. Particles outside the domain are frozen and take no part.
#include "core/equation_of_state.hpp"
#include "core/particle.hpp"
#include "neighbours/grid.hpp"

namespace sph {

// Moves a cell-relative offset along one axis into [0, cs), adjusting the cell coordinate.
SPH_HD void wrap_into_cell(real& off, int& c, real cs) {
    const real k = floor_r(off / cs);
    c += int(k);
    off -= k * cs;
    if (off >= cs) { off -= cs; ++c; }
    if (off < 0) off = 0;
}

// IntegrateBoundary = true moves boundary particles like fluid ones under their zero
// acceleration: the same result at more cost, kept only so that skip_bench can measure what
// not integrating them saves.
template <bool IntegrateBoundary = false>
SPH_HD void particle_kick_drift(std::uint32_t i, real4* pos, real4* velrho, std::uint32_t* cell, const real4* force,
                                real half_dt, real dt, const GridView& g, const PhysicsParams& p) {
    const std::uint32_t c = cell[i];
    if (c >= g.out_of_domain()) return;
    real4 vr = velrho[i];
    const real4 f = force[i];
    real4 ps = pos[i];
    const bool boundary = is_boundary(vr);
    real rho = density(vr) + half_dt * f.w;
    if (boundary && rho < p.rho0) rho = p.rho0;
    if (boundary && !IntegrateBoundary) {
        vr.w = -rho;
    } else {
        vr.x += half_dt * f.x;
        vr.y += half_dt * f.y;
        vr.z += half_dt * f.z;
        vr.w = boundary ? -rho : rho;
        ps.x += dt * vr.x;
        ps.y += dt * vr.y;
        ps.z += dt * vr.z;
        int3v cc = g.decode(c);
        wrap_into_cell(ps.x, cc.x, g.cell_size.x);
        wrap_into_cell(ps.y, cc.y, g.cell_size.y);
        wrap_into_cell(ps.z, cc.z, g.cell_size.z);
        if (g.any_periodic()) cc = g.wrap_periodic(cc);
        cell[i] = g.inside(cc.x, cc.y, cc.z) ? g.encode(cc.x, cc.y, cc.z) : g.out_of_domain();
    }
    velrho[i] = vr;
    ps.w = pressure_over_rho2(p, rho);
    pos[i] = ps;
}

template <bool IntegrateBoundary = false>
SPH_HD void particle_kick(std::uint32_t i, real4* velrho, const real4* force, real half_dt, const PhysicsParams& p) {
    real4 vr = velrho[i];
    const real4 f = force[i];
    real rho = density(vr) + half_dt * f.w;
    const bool boundary = is_boundary(vr);
    if (boundary && !IntegrateBoundary) {
        vr.w = -(rho < p.rho0 ? p.rho0 : rho);
    } else {
        vr.x += half_dt * f.x;
        vr.y += half_dt * f.y;
        vr.z += half_dt * f.z;
        vr.w = boundary ? -(rho < p.rho0 ? p.rho0 : rho) : rho;
    }
    velrho[i] = vr;
}

}  // namespace sph
