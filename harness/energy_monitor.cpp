#include "energy_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace sph {

double tait_internal_energy(const PhysicsParams& p, double rho) {
    const double rho0 = p.rho0, b = p.tait_b;
    // B (rho^6 / (6 rho0^7) + 1/rho - 7/(6 rho0)), written with r = rho/rho0 to keep it exact
    // near rho0: B / rho0 * (r^6 / 6 + 1/r - 7/6).
    const double r = rho / rho0;
    return b / rho0 * (std::pow(r, 6) / 6.0 + 1.0 / r - 7.0 / 6.0);
}

EnergySample measure_energy(const SnapshotData& s, const PhysicsParams& p, double dp) {
    EnergySample e;
    e.step = s.step;
    e.time = s.time;
    const double m = p.mass;
    const double g = std::sqrt(double(p.gravity.x) * p.gravity.x + double(p.gravity.y) * p.gravity.y +
                               double(p.gravity.z) * p.gravity.z);
    // Top of the water in each dp x dp column of the horizontal plane.
    std::unordered_map<long long, double> top;
    e.lowest_fluid = INFINITY;
    for (std::size_t i = 0; i < s.id.size(); ++i) {
        const double rho = s.density[i];
        if (s.type[i] != 0) {
            e.internal_boundary += m * tait_internal_energy(p, rho);
            continue;
        }
        const double x = s.position[3 * i], y = s.position[3 * i + 1], z = s.position[3 * i + 2];
        if (!std::isfinite(x)) continue;  // left the domain
        const double vx = s.velocity[3 * i], vy = s.velocity[3 * i + 1], vz = s.velocity[3 * i + 2];
        e.kinetic += 0.5 * m * (vx * vx + vy * vy + vz * vz);
        e.potential += m * g * z;
        e.internal_fluid += m * tait_internal_energy(p, rho);
        ++e.fluid;
        e.lowest_fluid = std::min(e.lowest_fluid, z);
        const long long key = (std::llround(x / dp) << 32) ^ (std::llround(y / dp) & 0xffffffffLL);
        auto [it, inserted] = top.emplace(key, z);
        if (!inserted && z > it->second) it->second = z;
    }
    e.fluid_mass = m * double(e.fluid);
    double sum = 0;
    for (const auto& [key, z] : top) sum += z;
    e.free_surface = top.empty() ? 0 : sum / double(top.size()) + 0.5 * dp;
    return e;
}

double energy_scale(const EnergySample& e0, const Scene& scene) {
    const double g = std::fabs(double(scene.params.gravity.z));
    return e0.kinetic + e0.potential - e0.fluid_mass * g * (e0.lowest_fluid - 0.5 * scene.dp);
}

}  // namespace sph
