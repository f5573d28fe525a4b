#pragma once
// Physical and numerical constants of a run, passed by value to every per-particle function.
#include "core/types.hpp"

namespace sph {

struct PhysicsParams {
    real h = 0;             // smoothing length
    real support = 0;       // kernel support radius (2h for both kernels)
    real support2 = 0;
    real mass = 0;          // particle mass (all particles share it)
    real rho0 = 1000;       // reference density
    real c0 = 0;            // reference sound speed
    real tait_b = 0;        // Tait B = c0^2 rho0 / gamma
    real alpha = 0.1;       // Monaghan artificial viscosity coefficient
    real nu = 0;            // kinematic viscosity of the laminar (Lo and Shao) term, m^2/s (0: off)
    real delta = 0.1;       // delta-SPH density diffusion coefficient (0: off)
    // Where the diffusion acts, DualSPHysics' two Fourtakas forms: false is its DensityDT 2,
    // the one its dam-break cases use, where a fluid particle with a wall particle inside its
    // support takes no diffusion at all (JSphGpu_ker.cu: deltap1 = FLT_MAX at the first wall
    // neighbour); true is DensityDT 3 ("full"), diffusion from the fluid neighbours whatever
    // the walls.
    bool diffusion_beside_walls = false;
    real shift = 0;         // particle shifting coefficient A, dr = -A h |v|max dt grad C (0: off)
    real eta2 = 0;          // 0.01 h^2, keeps viscosity and diffusion finite at r -> 0
    real3 gravity{0, 0, -9.81};
};

// Fills the derived constants from the primary ones.
inline PhysicsParams finish_params(PhysicsParams p) {
    p.support = 2 * p.h;
    p.support2 = p.support * p.support;
    p.tait_b = p.c0 * p.c0 * p.rho0 / 7;
    p.eta2 = real(0.01) * p.h * p.h;
    return p;
}

}  // namespace sph
