#include "validation/taylor_green.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"

namespace sph {
namespace {

double setting(const Scene& scene, const std::string& key) {
    auto it = scene.settings.find(key);
    if (it == scene.settings.end())
        throw InputError("the Taylor-Green error needs the scene setting '" + key + "', which scene '" + scene.name +
                         "' does not have");
    return std::stod(it->second);
}

}  // namespace

TaylorGreenError taylor_green_error(const SnapshotData& snapshot, const Scene& scene) {
    if (scene.name != "taylor-green")
        throw InputError("the Taylor-Green error applies to scene 'taylor-green', not '" + scene.name + "'");
    const double U = setting(scene, "U");
    const double k = 2 * std::numbers::pi / setting(scene, "wavelength");
    const double nu = double(scene.params.nu);  // the physical viscosity the run used
    const double decay = std::exp(-2 * nu * k * k * snapshot.time);
    const double mass = double(scene.params.mass);

    double diff2 = 0, exact2 = 0, energy = 0;
    std::size_t fluid = 0;
    for (std::size_t i = 0; i < snapshot.type.size(); ++i) {
        if (snapshot.type[i] != 0) continue;
        const double x = snapshot.position[3 * i], y = snapshot.position[3 * i + 1];
        if (!std::isfinite(x) || !std::isfinite(y)) continue;  // left the domain (cannot happen when periodic)
        const double ue = U * decay * std::sin(k * x) * std::cos(k * y);
        const double ve = -U * decay * std::cos(k * x) * std::sin(k * y);
        const double u = snapshot.velocity[3 * i], v = snapshot.velocity[3 * i + 1], w = snapshot.velocity[3 * i + 2];
        diff2 += (u - ue) * (u - ue) + (v - ve) * (v - ve) + w * w;
        exact2 += ue * ue + ve * ve;
        energy += 0.5 * mass * (u * u + v * v + w * w);
        ++fluid;
    }
    if (fluid == 0 || exact2 <= 0) throw InputError("the Taylor-Green error needs a snapshot with fluid particles");
    const double exact_energy = double(fluid) * mass * U * U / 4 * decay * decay;
    return {std::sqrt(diff2 / exact2), std::abs(energy - exact_energy) / exact_energy};
}

}  // namespace sph
