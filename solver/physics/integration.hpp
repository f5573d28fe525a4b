#pragma once
// The Verlet scheme of DualSPHysics (Verlet 1967; Crespo et al. 2015), one force evaluation
// per step, with forces F^n = (a^n, drho^n) computed at (x^n, v^n, rho^n):
//   x^{n+1}   = x^n + dt v^n + dt^2/2 a^n
//   v^{n+1}   = v^{n-1} + (dt^{n-1} + dt^n) a^n      rho^{n+1} = rho^{n-1} + (dt^{n-1} + dt^n) drho^n
// and every few steps an Euler step (v^{n+1} = v^n + dt a^n, rho likewise) that keeps the
// even and odd steps' chains together.
// Why not kick-drift-kick: pressure comes from density and density from the velocity field,
// and one force loop gives both rates from the same (v, rho). Kicking both from that state is
// forward Euler for the sound waves, which grow each step unless viscosity and diffusion
// damp them faster (measured: the hydrostatic tank diverged at CFL 0.2, and a still tank
// gained energy). The centred step above keeps them neutral (stable below CFL ~1).
// A particle that drifts through a periodic face re-enters on the other side: its cell
// index wraps and its offset inside the cell is kept.
// Boundary particles only integrate density (dynamic boundary), floored at rho0 as in
// DualSPHysics. Particles outside the domain are frozen and take no part.
// Particle shifting (p.shift = A > 0, flows without a free surface) moves a fluid particle
// further by dr = -A h U dt grad C with U the largest fluid speed (Sun et al. 2017 scale it
// by the flow's Mach number the same way), capped at U dt. The global U, not the particle's
// own speed, so that particles near stagnation points, where the lattice is stretched most,
// move. (The Simulation refuses shifting with Verlet lists, whose expiry does not count it.)
#include "core/equation_of_state.hpp"
#include "core/particle.hpp"
#include "neighbours/grid.hpp"

namespace sph {

// One step's rule: dt moves positions; velocity and density move over `span`, from the
// previous step's state (span = dt^{n-1} + dt^n) or, on an Euler step, the current one (dt).
struct TimeStep {
    real dt = 0;
    real span = 0;
    bool euler = true;
    real shift_speed = 0;  // particle shifting: the largest fluid speed (p.shift > 0 only)
};
inline TimeStep euler_step(real dt) { return {dt, dt, true}; }
inline TimeStep verlet_step(real dt, real previous_dt) { return {dt, dt + previous_dt, false}; }

// Moves a cell-relative offset along one axis into [0, cs), adjusting the cell coordinate.
SPH_HD void wrap_into_cell(real& off, int& c, real cs) {
    const real k = floor_r(off / cs);
    c += int(k);
    off -= k * cs;
    if (off >= cs) { off -= cs; ++c; }
    if (off < 0) off = 0;
}

// The (velocity, density) the step produces: what the update writes and what the step
// statistics check before it is written. Boundary particles keep their (zero) velocity
// unless Moving (skip_bench measures what not integrating them saves).
template <bool Moving>
SPH_HD real4 stepped_velrho(const real4& now, const real4& before, const real4& f, const TimeStep& s,
                            const PhysicsParams& p) {
    const real4& base = s.euler ? now : before;
    const real k = s.span;
    const bool boundary = is_boundary(now);
    real rho = density(base) + k * f.w;
    if (boundary && rho < p.rho0) rho = p.rho0;
    if (boundary && !Moving) return real4{now.x, now.y, now.z, -rho};
    return real4{base.x + k * f.x, base.y + k * f.y, base.z + k * f.z, boundary ? -rho : rho};
}

// The shift of fluid particle i (zero when shifting is off: grad_c is null).
SPH_HD real3 shifting_move(const real4& velrho, const real4* grad_c, std::uint32_t i, const TimeStep& s,
                           const PhysicsParams& p) {
    if (!grad_c || is_boundary(velrho)) return make3(0, 0, 0);
    const real reach = s.dt * s.shift_speed;
    real3 dr = (-p.shift * p.h * reach) * xyz(grad_c[i]);
    const real len = sqrt_r(dot(dr, dr));
    if (len > reach) dr = (reach / len) * dr;
    return dr;
}

// IntegrateBoundary = true moves boundary particles like fluid ones under their zero
// acceleration: the same result at more cost, kept only so that skip_bench can measure it.
// kept (empty unless the backend keeps them: the CUDA listed loop) follows cell, or, with a
// build frame, keeps the position against the cell of the last rebuild (KeptCells).
template <bool IntegrateBoundary = false>
SPH_HD void particle_advance(std::uint32_t i, real4* pos, real4* velrho, real4* velrho_prev, std::uint32_t* cell,
                             const KeptCells& kept, const real4* force, const real4* grad_c, const TimeStep& s,
                             const GridView& g, const PhysicsParams& p) {
    const std::uint32_t c = cell[i];
    if (c >= g.out_of_domain()) return;
    const real4 now = velrho[i];
    const real4 f = force[i];
    const real4 next = stepped_velrho<IntegrateBoundary>(now, velrho_prev[i], f, s, p);
    real4 ps = pos[i];
    real3 frame_shift{0, 0, 0};  // (cell - cell at the rebuild) * cell size, for kept.build_frame
    bool inside = true;
    if (!is_boundary(now) || IntegrateBoundary) {
        const real half_dt2 = real(0.5) * s.dt * s.dt;
        const real3 shift = shifting_move(now, grad_c, i, s, p);
        ps.x += s.dt * now.x + half_dt2 * f.x + shift.x;
        ps.y += s.dt * now.y + half_dt2 * f.y + shift.y;
        ps.z += s.dt * now.z + half_dt2 * f.z + shift.z;
        int3v cc = g.decode(c);
        wrap_into_cell(ps.x, cc.x, g.cell_size.x);
        wrap_into_cell(ps.y, cc.y, g.cell_size.y);
        wrap_into_cell(ps.z, cc.z, g.cell_size.z);
        if (g.any_periodic()) cc = g.wrap_periodic(cc);
        inside = g.inside(cc.x, cc.y, cc.z);
        cell[i] = inside ? g.encode(cc.x, cc.y, cc.z) : g.out_of_domain();
        if (kept.build_frame) {
            const CellCoords c0 = kept.coords[i];
            frame_shift = make3(real(cc.x - c0.x) * g.cell_size.x, real(cc.y - c0.y) * g.cell_size.y,
                                real(cc.z - c0.z) * g.cell_size.z);
        } else if (kept.coords) {
            kept.coords[i] = pack_cell_coords(cc, inside);
        }
    }
    velrho_prev[i] = now;
    velrho[i] = next;
    ps.w = pressure_over_rho2(p, density(next));  // what the next force loop reads
    pos[i] = ps;
    // While a particle stays in its rebuild's cell the shift is zero and the frame is pos to
    // the bit. One that left the domain is put far from every other, so that no pair with it
    // falls inside a support (the listed loop reads no cell that would say so). Open grids
    // only: across a periodic face the cell would jump by the period (the driver keeps no
    // frame there).
    if (kept.build_frame)
        kept.build_frame[i] = inside ? real4{ps.x + frame_shift.x, ps.y + frame_shift.y, ps.z + frame_shift.z, ps.w}
                                     : real4{real(1e15), real(1e15), real(1e15), ps.w};
}

}  // namespace sph
