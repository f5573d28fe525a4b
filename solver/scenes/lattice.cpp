#include "scenes/lattice.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace sph {

long lattice_index(double x, double dp) { return std::lround(x / dp); }

static void add_point(Scene& s, const double origin[3], long i, long j, long k) {
    s.position.push_back({origin[0] + s.dp * i, origin[1] + s.dp * j, origin[2] + s.dp * k});
    s.velocity.push_back({0, 0, 0});
}

void add_box_boundary(Scene& s, const double origin[3], const LatticeBox& b, int layers, bool open_top) {
    const long e = layers - 1;
    for (long i = b.lo[0] - e; i <= b.hi[0] + e; ++i)
        for (long j = b.lo[1] - e; j <= b.hi[1] + e; ++j)
            for (long k = b.lo[2] - e; k <= (open_top ? b.hi[2] : b.hi[2] + e); ++k) {
                const bool in_x = i > b.lo[0] && i < b.hi[0];
                const bool in_y = j > b.lo[1] && j < b.hi[1];
                const bool in_z = k > b.lo[2] && (k < b.hi[2] || open_top);
                if (in_x && in_y && in_z) continue;
                add_point(s, origin, i, j, k);
            }
}

void add_solid_box_surface(Scene& s, const double origin[3], const LatticeBox& b) {
    for (long i = b.lo[0]; i <= b.hi[0]; ++i)
        for (long j = b.lo[1]; j <= b.hi[1]; ++j)
            for (long k = b.lo[2] + 1; k <= b.hi[2]; ++k) {
                const bool surface = i == b.lo[0] || i == b.hi[0] || j == b.lo[1] || j == b.hi[1] || k == b.hi[2];
                if (surface) add_point(s, origin, i, j, k);
            }
}

void add_fluid_box(Scene& s, const double origin[3], const LatticeBox& b) {
    for (long i = b.lo[0]; i <= b.hi[0]; ++i)
        for (long j = b.lo[1]; j <= b.hi[1]; ++j)
            for (long k = b.lo[2]; k <= b.hi[2]; ++k) add_point(s, origin, i, j, k);
}

double pick_spacing(double dp, long long target, const std::function<long long(double)>& count,
                    const std::string& scene) {
    long long best_n = 0;
    double best_dp = dp;
    for (int it = 0; it < 30; ++it) {
        const long long n = count(dp);
        if (n > 0 && std::llabs(n - target) < std::llabs(best_n - target)) {
            best_n = n;
            best_dp = dp;
        }
        if (std::llabs(n - target) <= target / 100) return dp;
        // The count goes as dp^-3; damp the step so that lattice jumps do not make it cycle.
        const double ratio = n > 0 ? double(n) / double(target) : 0.5;
        dp *= std::pow(ratio, (it < 10 ? 1.0 : 0.5) / 3.0);
    }
    // Lattice counts are products of three step functions: scan near the best spacing for one
    // that lands within 1% (cheap for boxes; meshes converge above and never get here).
    for (int k = -400; k <= 400; ++k) {
        const double trial = best_dp * (1 + 0.0001 * k);
        const long long n = count(trial);
        if (std::llabs(n - target) <= target / 100) return trial;
        if (std::llabs(n - target) < std::llabs(best_n - target)) best_n = n;
    }
    std::ostringstream m;
    m << "scene '" << scene << "' cannot reach " << target << " fluid particles within 1% (closest: " << best_n
      << " at spacing " << best_dp << ")";
    throw InputError(m.str());
}

void set_common_physics(Scene& s, SceneOptions& opt, double c0, const char* default_kernel) {
    PhysicsParams& p = s.params;
    p.rho0 = opt.number("rho0", 1000, 1, 1e5);
    const double coef_h = opt.number("coef_h", 1.0, 0.5, 2.0);
    p.h = real(coef_h * std::sqrt(3.0) * s.dp);  // DualSPHysics' h = coefh sqrt(3 dp^2)
    p.mass = real(p.rho0 * s.dp * s.dp * s.dp);
    p.c0 = real(c0);
    p.alpha = real(opt.number("alpha", 0.1, 0, 10));
    p.delta = real(opt.number("delta", 0.1, 0, 1));
    // DualSPHysics' DensityDT 2 ("fourtakas", its dam break's) or 3 ("fourtakas-full"): params.hpp.
    const std::string diffusion = opt.text("density_diffusion", "fourtakas");
    if (diffusion == "fourtakas") p.diffusion_beside_walls = false;
    else if (diffusion == "fourtakas-full") p.diffusion_beside_walls = true;
    else throw InputError("option 'density_diffusion' must be 'fourtakas' or 'fourtakas-full', got '" + diffusion + "'");
    p.gravity = {0, 0, real(-opt.number("gravity", 9.81, 0, 1e3))};
    const std::string k = opt.text("kernel", default_kernel);
    if (k == "wendland") s.kernel = KernelType::wendland;
    else if (k == "cubic") s.kernel = KernelType::cubic;
    else throw InputError("option 'kernel' must be 'wendland' or 'cubic', got '" + k + "'");
    s.cfl = opt.number("cfl", 0.2, 1e-4, 1.0);
    p = finish_params(p);
}

}  // namespace sph
