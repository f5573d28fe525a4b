// Scenes of water in tanks: the dam break (ours and DualSPHysics' 01_DamBreak) and the
// hydrostatic tank. Every point sits on one lattice of spacing dp whose origin is the
// tank's inner corner, so walls and fluid never overlap.
#include <cmath>

#include "core/equation_of_state.hpp"
#include "core/error.hpp"
#include "scenes/lattice.hpp"

namespace sph {
namespace {

constexpr double g_default = 9.81;

// The spacing from either dp=... or particles=... (a fluid particle target within 1%).
double spacing_option(SceneOptions& opt, const std::string& scene, double default_dp, double fluid_volume,
                      const std::function<long long(double)>& count) {
    if (opt.has("particles") && opt.has("dp"))
        throw InputError("scene '" + scene + "' takes either 'dp' or 'particles', not both");
    if (opt.has("particles")) {
        const long long target = opt.integer("particles", 0, 8, 2'000'000'000LL);
        return pick_spacing(std::cbrt(fluid_volume / double(target)), target, count, scene);
    }
    return opt.number("dp", default_dp, 1e-6, 10);
}

void set_domain(Scene& s, const double lo[3], const double hi[3]) {
    for (int a = 0; a < 3; ++a) {
        s.lo[a] = lo[a];
        s.hi[a] = hi[a];
    }
}

}  // namespace

// DualSPHysics' example 01_DamBreak with its parameters: an open tank 1.6 x 0.67 x 0.4 m,
// a water column 0.4 x 0.67 x 0.3 m in the corner, a square column obstacle at (0.9, 0.24).
Scene make_dsph_dambreak(SceneOptions& opt) {
    Scene s;
    s.name = "dsph-dambreak";
    const double L = 1.6, W = 0.67, H = 0.4, fx = 0.4, fz = 0.3;
    auto fluid_box = [&](double dp) {
        return LatticeBox{{1, 1, 1}, {lattice_index(fx, dp), lattice_index(W, dp) - 1, lattice_index(fz, dp)}};
    };
    auto count = [&](double dp) {
        const LatticeBox b = fluid_box(dp);
        return (long long)(b.hi[0] - b.lo[0] + 1) * (b.hi[1] - b.lo[1] + 1) * (b.hi[2] - b.lo[2] + 1);
    };
    s.dp = spacing_option(opt, s.name, 0.0045, fx * W * fz, count);
    const bool obstacle = opt.integer("obstacle", 1, 0, 1) != 0;
    const double origin[3] = {0, 0, 0};
    const double dp = s.dp;
    add_box_boundary(s, origin, {{0, 0, 0}, {lattice_index(L, dp), lattice_index(W, dp), lattice_index(H, dp)}}, 1, true);
    s.bodies.push_back({"tank", 0, s.size()});
    if (obstacle) {
        const std::size_t first = s.size();
        add_solid_box_surface(s, origin, {{lattice_index(0.9, dp), lattice_index(0.24, dp), 0},
                                          {lattice_index(1.02, dp), lattice_index(0.36, dp), lattice_index(0.45, dp)}});
        s.bodies.push_back({"obstacle", first, s.size() - first});
    }
    s.n_boundary = s.size();
    add_fluid_box(s, origin, fluid_box(dp));
    const double g = opt.number("gravity", g_default, 0, 1e3);
    set_common_physics(s, opt, opt.number("c0_factor", 20, 1, 1000) * std::sqrt(g * fz), "cubic");
    const double lo[3] = {-2 * dp, -2 * dp, -2 * dp}, hi[3] = {L + 2 * dp, W + 2 * dp, 1.5 * H};
    set_domain(s, lo, hi);
    opt.finish(s.name);
    s.settings = opt.resolved();
    return s;
}

// A water column collapsing in a tank: column_width x width x column_height in the corner of
// a length x width x height open tank (Martin and Moyce's geometry when height = 2 width).
// initial_speed = U (m/s) launches the column at the far wall: a high-speed impact.
Scene make_dambreak(SceneOptions& opt) {
    Scene s;
    s.name = "dambreak";
    const double L = opt.number("length", 2.0, 0.01, 100), W = opt.number("width", 0.2, 0.01, 100);
    const double H = opt.number("height", 1.2, 0.01, 100);
    const double a = opt.number("column_width", 0.5, 0.01, 100), b = opt.number("column_height", 1.0, 0.01, 100);
    if (a >= L || b >= H) throw InputError("scene 'dambreak': the column must fit inside the tank");
    const int layers = int(opt.integer("layers", 2, 1, 5));
    auto fluid_box = [&](double dp) {
        return LatticeBox{{1, 1, 1}, {lattice_index(a, dp), lattice_index(W, dp) - 1, lattice_index(b, dp)}};
    };
    auto count = [&](double dp) {
        const LatticeBox f = fluid_box(dp);
        return (long long)(f.hi[0]) * (f.hi[1]) * (f.hi[2]);
    };
    s.dp = spacing_option(opt, s.name, 0.02, a * W * b, count);
    const double origin[3] = {0, 0, 0};
    add_box_boundary(s, origin, {{0, 0, 0}, {lattice_index(L, s.dp), lattice_index(W, s.dp), lattice_index(H, s.dp)}},
                     layers, true);
    s.n_boundary = s.size();
    s.bodies = {{"tank", 0, s.n_boundary}};
    add_fluid_box(s, origin, fluid_box(s.dp));
    // A high-speed impact: the column starts moving towards the far wall. Read only when
    // given, so that the default scene's resolved settings (and results) stay as they were.
    if (opt.has("initial_speed")) {
        const float u = float(opt.number("initial_speed", 0, 0, 1e3));
        for (std::size_t i = s.n_boundary; i < s.size(); ++i) s.velocity[i] = {u, 0, 0};
    }
    const double g = opt.number("gravity", g_default, 0, 1e3);
    set_common_physics(s, opt, opt.number("c0_factor", 20, 1, 1000) * std::sqrt(g * b), "wendland");
    const double m = (layers + 1) * s.dp;
    const double lo[3] = {-m, -m, -m}, hi[3] = {L + m, W + m, H + m};
    set_domain(s, lo, hi);
    opt.finish(s.name);
    s.settings = opt.resolved();
    return s;
}

// Still water of depth `depth` in an open tank, started at hydrostatic density.
Scene make_tank(SceneOptions& opt) {
    Scene s;
    s.name = "tank";
    const double L = opt.number("length", 0.4, 0.01, 100), W = opt.number("width", 0.2, 0.01, 100);
    const double D = opt.number("depth", 0.4, 0.01, 100);
    const int layers = int(opt.integer("layers", 3, 1, 5));
    auto fluid_box = [&](double dp) {
        return LatticeBox{{1, 1, 1}, {lattice_index(L, dp) - 1, lattice_index(W, dp) - 1, lattice_index(D, dp)}};
    };
    auto count = [&](double dp) {
        const LatticeBox f = fluid_box(dp);
        return (long long)(f.hi[0]) * (f.hi[1]) * (f.hi[2]);
    };
    s.dp = spacing_option(opt, s.name, 0.02, L * W * D, count);
    const double origin[3] = {0, 0, 0};
    const long top = lattice_index(D * 1.25, s.dp) + 2;
    add_box_boundary(s, origin, {{0, 0, 0}, {lattice_index(L, s.dp), lattice_index(W, s.dp), top}}, layers, true);
    s.n_boundary = s.size();
    s.bodies = {{"tank", 0, s.n_boundary}};
    const LatticeBox f = fluid_box(s.dp);
    add_fluid_box(s, origin, f);
    const double g = opt.number("gravity", g_default, 0, 1e3);
    set_common_physics(s, opt, opt.number("c0_factor", 20, 1, 1000) * std::sqrt(g * D), "wendland");
    // Hydrostatic start: the free surface sits half a spacing above the top layer.
    const double surface = (double(f.hi[2]) + 0.5) * s.dp;
    s.settings["free_surface"] = std::to_string(surface);
    s.density.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        const double depth = std::max(0.0, surface - s.position[i][2]);
        const double p = s.params.rho0 * g * depth;
        s.density[i] = float(s.params.rho0 * std::pow(1 + p / s.params.tait_b, 1.0 / 7.0));
    }
    const double m = (layers + 1) * s.dp;
    const double lo[3] = {-m, -m, -m}, hi[3] = {L + m, W + m, top * s.dp + m};
    set_domain(s, lo, hi);
    opt.finish(s.name);
    s.settings = opt.resolved();
    s.settings["free_surface"] = std::to_string(surface);
    return s;
}

}  // namespace sph
