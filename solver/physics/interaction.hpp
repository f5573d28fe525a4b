#pragma once
// The pair interaction of weakly compressible SPH, written once for both backends:
//   continuity  d rho_i/dt = sum_j m (v_i - v_j) . grad W_ij   (+ delta-SPH diffusion, fluid pairs)
//   momentum    dv_i/dt    = -sum_j m (P_i/rho_i^2 + P_j/rho_j^2 + Pi_ij) grad W_ij + g
// with Monaghan's artificial viscosity Pi_ij. Boundary particles (dynamic boundary
// conditions) gather density from fluid neighbours only and do not move.
#include "core/params.hpp"
#include "core/particle.hpp"
#include "neighbours/cell_search.hpp"

namespace sph {

// What the force loop reads: the sorted particle arrays of one subdomain.
struct ForceInputs {
    const real4* pos;
    const real4* velrho;
    const std::uint32_t* cell;
    const std::uint32_t* cell_start;
    GridView grid;
};

// Returns (acceleration, d rho / dt) of particle i.
template <class Kernel, class Search, bool Diffusion>
SPH_HD real4 particle_force(std::uint32_t i, const ForceInputs& in, const PhysicsParams& p, const Kernel& kernel) {
    const real4 pos_i = in.pos[i];
    const real4 vr_i = in.velrho[i];
    const bool fluid_i = !is_boundary(vr_i);
    const real rho_i = density(vr_i);
    const real3 off_i = xyz(pos_i);
    const real3 v_i = xyz(vr_i);
    const real cs = in.grid.cell_size;
    const real diffusion_coef = Diffusion ? 2 * p.delta * p.h * p.c0 * p.mass : real(0);
    const real visc_coef = p.alpha * p.h * p.c0;

    real3 acc{0, 0, 0};
    real drho = 0;
    Search::visit(in.grid, in.cell_start, in.cell, in.grid.decode(in.cell[i]),
                  [&](std::uint32_t j, int dx, int dy, int dz) {
                      const real4 pos_j = in.pos[j];
                      // x_i - x_j = (cell_i - cell_j) * cs + off_i - off_j, exact in the cell part.
                      const real3 rij = make3(off_i.x - pos_j.x - dx * cs, off_i.y - pos_j.y - dy * cs,
                                              off_i.z - pos_j.z - dz * cs);
                      const real r2 = dot(rij, rij);
                      if (r2 >= p.support2 || r2 <= real(1e-18) * p.support2) return;  // outside, or itself
                      const real4 vr_j = in.velrho[j];
                      const bool fluid_j = !is_boundary(vr_j);
                      if (!fluid_i && !fluid_j) return;  // boundary-boundary pairs do nothing
                      const real fac = kernel.grad_factor(sqrt_r(r2));
                      const real3 vij = v_i - xyz(vr_j);
                      const real vdotr = dot(vij, rij);
                      drho += p.mass * fac * vdotr;  // m (v_ij . r_ij) F, with grad W = r_ij F
                      const real rho_j = density(vr_j);
                      if (Diffusion && fluid_i && fluid_j)
                          drho += diffusion_coef * (rho_i - rho_j) / rho_j * r2 * fac / (r2 + p.eta2);
                      if (fluid_i) {
                          real pi_ij = 0;
                          if (vdotr < 0) pi_ij = -visc_coef * vdotr / ((r2 + p.eta2) * real(0.5) * (rho_i + rho_j));
                          const real s = -p.mass * (pos_i.w + pos_j.w + pi_ij) * fac;
                          acc += s * rij;
                      }
                  });
    if (fluid_i) acc += p.gravity;
    return make4(acc, drho);
}

// Work counters of one particle's search (candidates visited, real neighbours, ranges visited).
struct SearchWork {
    unsigned long long candidates = 0, neighbours = 0, ranges = 0;
};

template <class Search>
SPH_HD SearchWork particle_search_work(std::uint32_t i, const ForceInputs& in, const PhysicsParams& p) {
    SearchWork w;
    const real3 off_i = xyz(in.pos[i]);
    const real cs = in.grid.cell_size;
    const int3v c = in.grid.decode(in.cell[i]);
    Search::visit(in.grid, in.cell_start, in.cell, c, [&](std::uint32_t j, int dx, int dy, int dz) {
        const real4 pj = in.pos[j];
        const real3 rij = make3(off_i.x - pj.x - dx * cs, off_i.y - pj.y - dy * cs, off_i.z - pj.z - dz * cs);
        const real r2 = dot(rij, rij);
        ++w.candidates;
        if (r2 < p.support2 && r2 > real(1e-18) * p.support2) ++w.neighbours;
    });
    // Ranges visited: one per cell (or per merged z-run) of the stencil that lies in the grid.
    const int n = Search::n;
    int cols = 0, runs = 0;
    for (int dx = -n; dx <= n; ++dx)
        for (int dy = -n; dy <= n; ++dy)
            if (in.grid.inside(c.x + dx, c.y + dy, 0)) ++cols;
    for (int dz = -n; dz <= n; ++dz)
        if (c.z + dz >= 0 && c.z + dz < in.grid.nz) ++runs;
    w.ranges = (unsigned long long)cols * (Search::merge ? 1 : runs);
    return w;
}

}  // namespace sph
