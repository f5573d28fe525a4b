#pragma once
// Per-step reductions: what the CFL time step needs (largest acceleration and velocity),
// what the per-step CSV reports (kinetic energy, density range), and the blow-up check.
// They are taken over the state the step's update is about to produce, so a blow-up is caught
// before it is written and the state in memory is still the last good one.
#include <cfloat>

#include "core/params.hpp"
#include "core/particle.hpp"
#include "physics/integration.hpp"

namespace sph {

enum class BlowUp : std::uint32_t { none = 0, acceleration = 1, velocity = 2, density = 3 };

struct StatsLimits {
    real max_speed = 0;  // a fluid speed above this is a blow-up (default: the sound speed)
    real min_density = 0, max_density = 0;
};

struct StepStats {
    real max_accel2 = 0;  // fluid only
    real max_speed2 = 0;
    double kinetic_energy = 0;
    real min_density = FLT_MAX, max_density = 0;  // fluid only
    std::uint32_t fluid_count = 0;
    std::uint32_t bad_id = 0xffffffffu;  // smallest id of a particle that blew up
    std::uint32_t bad_what = 0;          // BlowUp
};

SPH_HD StepStats merge_stats(const StepStats& a, const StepStats& b) {
    StepStats r;
    r.max_accel2 = a.max_accel2 > b.max_accel2 ? a.max_accel2 : b.max_accel2;
    r.max_speed2 = a.max_speed2 > b.max_speed2 ? a.max_speed2 : b.max_speed2;
    r.kinetic_energy = a.kinetic_energy + b.kinetic_energy;
    r.min_density = a.min_density < b.min_density ? a.min_density : b.min_density;
    r.max_density = a.max_density > b.max_density ? a.max_density : b.max_density;
    r.fluid_count = a.fluid_count + b.fluid_count;
    const bool take_b = b.bad_id < a.bad_id;
    r.bad_id = take_b ? b.bad_id : a.bad_id;
    r.bad_what = take_b ? b.bad_what : a.bad_what;
    return r;
}

SPH_HD StepStats particle_stats(std::uint32_t i, const real4* velrho, const real4* velrho_prev, const real4* force,
                                const std::uint32_t* id, const TimeStep& step, const PhysicsParams& p,
                                const StatsLimits& lim) {
    StepStats s;
    const real4 vr = velrho[i];
    if (is_boundary(vr)) return s;
    const real4 f = force[i];
    const real4 next = stepped_velrho<true>(vr, velrho_prev[i], f, step, p);
    const real3 v = xyz(next);
    const real rho = next.w;
    s.max_accel2 = f.x * f.x + f.y * f.y + f.z * f.z;
    s.max_speed2 = dot(v, v);
    s.kinetic_energy = 0.5 * double(p.mass) * double(s.max_speed2);
    s.min_density = s.max_density = rho;
    s.fluid_count = 1;
    BlowUp what = BlowUp::none;
    if (!finite_r(s.max_accel2) || !finite_r(f.w)) what = BlowUp::acceleration;
    else if (!finite_r(s.max_speed2) || s.max_speed2 > lim.max_speed * lim.max_speed) what = BlowUp::velocity;
    else if (!(rho >= lim.min_density && rho <= lim.max_density)) what = BlowUp::density;
    if (what != BlowUp::none) {
        s.bad_id = id[i];
        s.bad_what = std::uint32_t(what);
        s.max_accel2 = s.max_speed2 = 0;
        s.kinetic_energy = 0;
    }
    return s;
}

}  // namespace sph
