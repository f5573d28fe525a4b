#pragma once
// The energy budget and the free-surface height of a state, measured on the host from a
// snapshot (absolute positions in double precision), for the stability studies.
//
// Weakly compressible SPH with a symmetric pressure term conserves, in continuous time and
// without viscosity or diffusion, E = kinetic + potential + internal, where the internal
// (elastic) energy per unit mass of the Tait equation P(rho) is e(rho) = int P / rho^2 drho:
//   e(rho) = B (rho^6 / (6 rho0^7) + 1 / rho - 7 / (6 rho0)),  e(rho0) = 0.
// A hydrostatic start stores elastic energy that trades with potential energy as the water
// settles, so a drift measured without it would mistake that exchange for an error.
// Boundary particles (dynamic boundary: fixed, density integrated) carry elastic energy too;
// it is kept apart since walls are not water. Artificial viscosity dissipates E; that, and the
// integrator's error, is the drift the studies report.
#include "core/params.hpp"
#include "io/snapshot_writer.hpp"
#include "scenes/scene.hpp"

namespace sph {

struct EnergySample {
    long step = 0;
    double time = 0;
    double kinetic = 0;            // sum 1/2 m v^2 over fluid
    double potential = 0;          // sum m |g| z over fluid (z from the world origin)
    double internal_fluid = 0;     // sum m e(rho) over fluid
    double internal_boundary = 0;  // sum m e(rho) over boundary particles
    double free_surface = 0;       // mean over occupied dp x dp columns of the top fluid particle, + dp/2
    double lowest_fluid = 0;       // z of the lowest fluid particle
    double fluid_mass = 0;
    std::size_t fluid = 0;         // fluid particles inside the domain

    double mechanical() const { return kinetic + potential + internal_fluid; }
    double total() const { return mechanical() + internal_boundary; }
};

// Tait elastic energy per unit mass, zero at rho0.
double tait_internal_energy(const PhysicsParams& p, double rho);

EnergySample measure_energy(const SnapshotData& state, const PhysicsParams& params, double dp);

// What drifts are divided by: the initial kinetic energy plus the potential energy above the
// lowest fluid particle's floor (its z less dp/2), independent of the world's origin.
double energy_scale(const EnergySample& initial, const Scene& scene);

}  // namespace sph
