#pragma once
// How far a Taylor-Green vortex run is from the exact solution (scene 'taylor-green'):
//   u = U sin(kx) cos(ky) F,  v = -U cos(kx) sin(ky) F,  F(t) = exp(-2 nu k^2 t).
#include "io/snapshot_writer.hpp"
#include "scenes/scene.hpp"

namespace sph {

struct TaylorGreenError {
    // ||u_sph - u_exact|| / ||u_exact|| over the fluid particles, u_exact at each particle's
    // position at the snapshot's time (discrete L2 norms; all particles have one mass).
    double velocity_l2;
    // |E_sph - E_exact| / E_exact, with E = sum 1/2 m |u|^2 over the fluid and
    // E_exact = M U^2 / 4 F(t)^2 (what the initial lattice holds, decayed exactly).
    double energy_decay_error;
};

// The scene must be the one the run started from (its U, wavelength and nu). Throws
// InputError for another scene or a snapshot without fluid.
TaylorGreenError taylor_green_error(const SnapshotData& snapshot, const Scene& scene);

}  // namespace sph
