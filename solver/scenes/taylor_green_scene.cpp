// The 2D Taylor-Green vortex, a viscous flow with an exact solution in time:
//   u = U sin(kx) cos(ky) F(t),  v = -U cos(kx) sin(ky) F(t),  F(t) = exp(-2 nu k^2 t)
//   p = rho0 U^2 / 4 (cos 2kx + cos 2ky) F(t)^2
// in a box one wavelength (2 pi / k) wide, periodic in x, y and z. z is a few particle
// layers thick and carries no flow, so the 3D solver sees a 2D flow.
#include <cmath>
#include <numbers>

#include "core/equation_of_state.hpp"
#include "core/error.hpp"
#include "scenes/scene.hpp"

namespace sph {

Scene make_taylor_green(SceneOptions& opt) {
    Scene s;
    s.name = "taylor-green";
    const double wavelength = opt.number("wavelength", 1.0, 1e-6, 1e3);
    const long per_wavelength = long(opt.integer("resolution", 32, 8, 2048));
    const long layers = long(opt.integer("layers", 4, 1, 64));
    const double U = opt.number("U", 1.0, 1e-6, 1e3);
    if (opt.has("reynolds") && opt.has("nu"))
        throw InputError("scene 'taylor-green' takes either 'reynolds' or 'nu', not both");
    // Re = U wavelength / nu (the convention of Adami, Hu and Adams 2013, whose box is one
    // wavelength wide).
    const double nu = opt.has("nu") ? opt.number("nu", 0, 1e-12, 1e6)
                                     : U * wavelength / opt.number("reynolds", 100, 1e-3, 1e7);
    s.dp = wavelength / double(per_wavelength);

    PhysicsParams& p = s.params;
    p.rho0 = real(opt.number("rho0", 1000, 1, 1e5));
    p.h = real(opt.number("coef_h", 1.0, 0.5, 2.0) * std::sqrt(3.0) * s.dp);
    p.mass = real(double(p.rho0) * s.dp * s.dp * s.dp);
    p.c0 = real(opt.number("c0_factor", 10, 1, 1000) * U);  // Mach 0.1 by default
    p.alpha = real(opt.number("alpha", 0, 0, 10));  // the physical viscosity is nu; no artificial one by default
    p.delta = real(opt.number("delta", 0.1, 0, 1));
    // Particle shifting (integration.hpp), on by default: without it the lattice stretched at
    // the stagnation points ruins the run after about 0.12 s at Re 100 (README).
    p.shift = real(opt.number("shifting", 16, 0, 100));
    p.nu = real(nu);
    p.gravity = {0, 0, 0};
    const std::string kernel = opt.text("kernel", "wendland");
    if (kernel == "wendland") s.kernel = KernelType::wendland;
    else if (kernel == "cubic") s.kernel = KernelType::cubic;
    else throw InputError("option 'kernel' must be 'wendland' or 'cubic', got '" + kernel + "'");
    s.cfl = opt.number("cfl", 0.2, 1e-4, 1.0);
    p = finish_params(p);
    if (double(layers) * s.dp < double(p.support))
        throw InputError("scene 'taylor-green' needs its z period (layers x spacing) to be at least the kernel support: "
                         "raise 'layers' to " + std::to_string(long(std::ceil(double(p.support) / s.dp))));

    // Particles at cell centres of a dp lattice, so every period holds whole layers.
    const double k = 2 * std::numbers::pi / wavelength;
    for (long ix = 0; ix < per_wavelength; ++ix)
        for (long iy = 0; iy < per_wavelength; ++iy)
            for (long iz = 0; iz < layers; ++iz) {
                const double x = (double(ix) + 0.5) * s.dp, y = (double(iy) + 0.5) * s.dp;
                s.position.push_back({x, y, (double(iz) + 0.5) * s.dp});
                s.velocity.push_back({float(U * std::sin(k * x) * std::cos(k * y)),
                                      float(-U * std::cos(k * x) * std::sin(k * y)), 0.0f});
                // The exact pressure through the Tait EOS: rho = rho0 (1 + P / B)^(1/7).
                const double pressure = double(p.rho0) * U * U / 4 * (std::cos(2 * k * x) + std::cos(2 * k * y));
                s.density.push_back(float(double(p.rho0) * std::pow(1 + pressure / double(p.tait_b), 1.0 / 7.0)));
            }
    s.n_boundary = 0;
    s.lo = {0, 0, 0};
    s.hi = {wavelength, wavelength, double(layers) * s.dp};
    s.periodic = {true, true, true};
    opt.finish(s.name);
    s.settings = opt.resolved();
    s.settings["nu"] = std::to_string(nu);  // resolved either way, for provenance and the error metric
    return s;
}

}  // namespace sph
