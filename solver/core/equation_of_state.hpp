#pragma once
// Tait equation of state with gamma = 7: P = B ((rho / rho0)^7 - 1), B = c0^2 rho0 / 7.
#include "core/params.hpp"

namespace sph {

SPH_HD real tait_pressure(const PhysicsParams& p, real rho) {
    const real r = rho / p.rho0;
    const real r2 = r * r;
    const real r4 = r2 * r2;
    return p.tait_b * (r4 * r2 * r - 1);
}

// What the force loop reads per neighbour: P / rho^2, precomputed once per particle.
SPH_HD real pressure_over_rho2(const PhysicsParams& p, real rho) {
    return tait_pressure(p, rho) / (rho * rho);
}

}  // namespace sph
