// The solver against simple references: forces against a brute-force float64 evaluation,
// conservation laws, hydrostatics, shift invariance, and the failure paths.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "core/equation_of_state.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

// dW/dr / r of the Wendland C2 kernel, in double.
double wendland_grad_factor(double r, double h) {
    const double q = r / h;
    if (q >= 2) return 0;
    const double t = 1 - q / 2;
    return 21.0 / (16.0 * M_PI * h * h * h) * -5.0 * t * t * t / (h * h);
}

// The cubic spline's shape (W without its 1 / (pi h^3)) and dW/dr / r, in double.
double cubic_shape(double q) { return q < 1 ? 1 - 1.5 * q * q + 0.75 * q * q * q : q < 2 ? 0.25 * (2 - q) * (2 - q) * (2 - q) : 0; }
double cubic_grad_factor(double r, double h) {
    const double q = r / h, norm = 1 / (M_PI * h * h * h);
    if (q >= 2) return 0;
    return q < 1 ? norm * (-3 + 2.25 * q) / (h * h) : norm * -0.75 * (2 - q) * (2 - q) / (h * r);
}

// The pressure and continuity terms read the current state, the dissipative ones (artificial
// viscosity, density diffusion with its hydrostatic correction) the previous step's: the two
// are drawn independently here, so a term reading the wrong one shows.
// Run on the host (the simple loop) and on the GPU with two searches (the gathered force
// loop of cuda_cell_forces.cu, with its approximate division and square root), skipped without
// a GPU. The printed errors are the figures docs/force-loop-notes.md reports.
struct ForceCase {
    BackendKind backend;
    int n;
    bool merge;
    bool diffusion_beside_walls;
    bool cubic = false;  // the cubic spline (with its tensile correction), else Wendland
};
class Forces : public ::testing::TestWithParam<ForceCase> {};

TEST_P(Forces, MatchABruteForceFloat64Reference) {
    const ForceCase fc = GetParam();
    if (fc.backend == BackendKind::cuda && !cuda_backend_available())
        GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    Scene s = test::random_scene(1200, 300, 0.25, 0.02, 42u, 0.0, 0.5);
    s.params.gravity = {0, real(-3), real(-9.81)};
    s.params.diffusion_beside_walls = fc.diffusion_beside_walls;
    if (fc.cubic) s.kernel = KernelType::cubic;
    // The walls in a floor slab (the lowest fifth), so that some fluid particles have a wall
    // inside their support and the others none: the diffusion's wall rule acts on both kinds.
    for (std::size_t k = 0; k < s.n_boundary; ++k) s.position[k][2] *= 0.2;
    const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, fc.n);
    const SubdomainConfig cfg{s.params, g.view, s.kernel, true, {fc.n, fc.merge}};
    auto d = fc.backend == BackendKind::cuda ? make_cuda_subdomain(cfg, s.size(), 0) : make_host_subdomain(cfg, s.size());
    ParticleArrays state = make_particle_arrays(s, g);
    std::mt19937 rng(43u);
    std::uniform_real_distribution<double> dv(-0.5, 0.5), drho(0.99, 1.01);
    std::vector<std::array<double, 4>> old(s.size());  // by id: previous velocity and density
    for (std::size_t k = 0; k < state.size(); ++k) {
        const bool boundary = k < s.n_boundary;
        old[k] = {boundary ? 0 : dv(rng), boundary ? 0 : dv(rng), boundary ? 0 : dv(rng), 1000 * drho(rng)};
        state.velrho_prev.push_back(
            make_velrho(make3(real(old[k][0]), real(old[k][1]), real(old[k][2])), real(old[k][3]), boundary));
        state.pos[k].w = pressure_over_rho2(s.params, density(state.velrho[k]));
    }
    d->upload(state);
    d->sort_by_cell();
    d->compute_forces();
    const ParticleArrays a = d->download();

    const std::size_t n = s.size();
    std::vector<double> rho(n);
    std::vector<std::array<double, 4>> fast(n);
    for (std::size_t k = 0; k < n; ++k) {
        rho[a.id[k]] = density(a.velrho[k]);
        fast[a.id[k]] = {a.force[k].x, a.force[k].y, a.force[k].z, a.force[k].w};
    }
    const PhysicsParams& p = s.params;
    const double h = p.h, m = p.mass, c0 = p.c0, eta2 = 0.01 * h * h, B = c0 * c0 * p.rho0 / 7;
    const double gravity[3] = {p.gravity.x, p.gravity.y, p.gravity.z};
    auto pressure = [&](double r) { return B * (std::pow(r / p.rho0, 7) - 1); };
    double err_a = 0, norm_a = 0, err_d = 0, norm_d = 0;
    std::size_t beside_walls = 0;  // fluid particles with a wall inside their support
    for (std::size_t i = 0; i < n; ++i) {
        const bool fi = i >= s.n_boundary;
        double acc[3] = {0, 0, 0}, drho = 0, diffusion = 0;
        bool near_wall = false;
        for (std::size_t j = 0; j < n; ++j) {
            const bool fj = j >= s.n_boundary;
            if (i == j || (!fi && !fj)) continue;
            double r[3], r2 = 0, vr = 0, old_vr = 0, gr = 0;
            for (int k = 0; k < 3; ++k) {
                r[k] = s.position[i][k] - s.position[j][k];
                r2 += r[k] * r[k];
                vr += (double(s.velocity[i][k]) - double(s.velocity[j][k])) * r[k];
                old_vr += (old[i][k] - old[j][k]) * r[k];
                gr += gravity[k] * r[k];
            }
            if (r2 >= 4 * h * h) continue;
            const double f = fc.cubic ? cubic_grad_factor(std::sqrt(r2), h) : wendland_grad_factor(std::sqrt(r2), h);
            drho += m * f * vr * rho[i] / rho[j];  // DualSPHysics' continuity form
            // Fourtakas et al.: only the density difference beyond the hydrostatic one diffuses.
            const double dynamic = old[i][3] - old[j][3] - p.rho0 * gr / (c0 * c0);
            if (fi && fj) diffusion += 2 * p.delta * h * c0 * m * dynamic / old[j][3] * r2 * f / (r2 + eta2);
            // DualSPHysics' DensityDT 2: a wall inside the support takes all of i's diffusion away.
            if (fi && !fj) near_wall = true;
            if (fi) {
                const double pi =
                    old_vr < 0 ? -p.alpha * h * c0 * old_vr / ((r2 + eta2) * 0.5 * (rho[i] + rho[j])) : 0;
                double c = (pressure(rho[i]) + pressure(rho[j])) / (rho[i] * rho[j]) + pi;  // and momentum form
                if (fc.cubic) {  // Monaghan's tensile correction, as DualSPHysics applies it
                    const double fab = std::pow(cubic_shape(std::sqrt(r2) / h) / cubic_shape(2.0 / 3.0), 4);
                    auto part = [&](double rho_k) {
                        const double w = pressure(rho_k) / (rho_k * rho_k);
                        return w * (w > 0 ? 0.01 : -0.2);
                    };
                    c += fab * (part(rho[i]) + part(rho[j]));
                }
                for (int k = 0; k < 3; ++k) acc[k] -= m * c * f * r[k];
            }
        }
        if (!near_wall || p.diffusion_beside_walls) drho += diffusion;
        beside_walls += near_wall;
        for (int k = 0; k < 3; ++k) {
            if (fi) acc[k] += gravity[k];
            err_a += (fast[i][k] - acc[k]) * (fast[i][k] - acc[k]);
            norm_a += acc[k] * acc[k];
        }
        err_d += (fast[i][3] - drho) * (fast[i][3] - drho);
        norm_d += drho * drho;
    }
    ASSERT_GT(norm_a, 0);
    ASSERT_GT(norm_d, 0);
    // Both kinds of fluid particle must be there for the diffusion's wall rule to be tested.
    ASSERT_GT(beside_walls, 0u);
    ASSERT_LT(beside_walls, n - s.n_boundary);
    std::printf("forces against float64 (%s, n = %d, merge = %d, diffusion beside walls = %d; %zu of %zu fluid "
                "particles beside walls): relative RMS error %.3g (acceleration), %.3g (density rate)\n",
                fc.backend == BackendKind::cuda ? "cuda" : "host", fc.n, int(fc.merge), int(fc.diffusion_beside_walls),
                beside_walls, n - s.n_boundary, std::sqrt(err_a / norm_a), std::sqrt(err_d / norm_d));
    EXPECT_LT(std::sqrt(err_a / norm_a), 1e-4);
    EXPECT_LT(std::sqrt(err_d / norm_d), 1e-4);
}

INSTANTIATE_TEST_SUITE_P(Backends, Forces,
                         ::testing::Values(ForceCase{BackendKind::host, 1, false, false},
                                           ForceCase{BackendKind::host, 1, false, true},
                                           ForceCase{BackendKind::cuda, 1, false, false},
                                           ForceCase{BackendKind::cuda, 1, false, true},
                                           ForceCase{BackendKind::cuda, 2, true, false},
                                           ForceCase{BackendKind::host, 1, false, false, true},
                                           ForceCase{BackendKind::cuda, 1, false, false, true},
                                           ForceCase{BackendKind::cuda, 2, true, false, true}),
                         [](const auto& info) {
                             return std::string(info.param.backend == BackendKind::cuda ? "cuda" : "host") + "_n" +
                                    std::to_string(info.param.n) + (info.param.merge ? "_merged" : "_cells") +
                                    (info.param.diffusion_beside_walls ? "_diffusion_beside_walls" : "") +
                                    (info.param.cubic ? "_cubic" : "");
                         });

TEST(Conservation, MomentumAndMassWithoutWallsOrGravity) {
    Scene s = test::random_scene(1500, 0, 0.2, 0.02, 7u, 0.2, 0.5);
    SolverOptions opt;
    Simulation sim(s, opt);
    auto momentum = [&](const SnapshotData& snap) {
        std::array<double, 4> p{0, 0, 0, 0};  // px, py, pz, sum m |v|
        for (std::size_t i = 0; i < snap.id.size(); ++i) {
            double speed2 = 0;
            for (int k = 0; k < 3; ++k) {
                p[k] += double(s.params.mass) * snap.velocity[3 * i + k];
                speed2 += double(snap.velocity[3 * i + k]) * snap.velocity[3 * i + k];
            }
            p[3] += double(s.params.mass) * std::sqrt(speed2);
        }
        return p;
    };
    const auto p0 = momentum(sim.snapshot());
    for (int k = 0; k < 40; ++k) sim.step();
    const SnapshotData end = sim.snapshot();
    const auto p1 = momentum(end);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p1[k], p0[k], 2e-5 * p0[3]) << "component " << k;
    // Mass: every particle still there, exactly once.
    std::set<std::uint32_t> ids(end.id.begin(), end.id.end());
    EXPECT_EQ(ids.size(), s.size());
    EXPECT_EQ(sim.steps_taken(), 40);
}

TEST(Hydrostatics, TankSettlesToRhoGH) {
    const Scene s = make_scene("tank", {{"length", "0.15"}, {"width", "0.075"}, {"depth", "0.2"}, {"dp", "0.0125"}});
    Simulation sim(s, SolverOptions{});
    for (int k = 0; k < 400; ++k) sim.step();
    const SnapshotData snap = sim.snapshot();
    // The free surface as it settled: the top fluid layer, plus half a spacing.
    double top = -1e9;
    for (std::size_t i = 0; i < snap.id.size(); ++i)
        if (snap.type[i] == 0) top = std::max(top, snap.position[3 * i + 2]);
    const double surface = top + 0.5 * s.dp;
    auto mean_pressure_at = [&](double depth) {
        const double z = surface - depth;
        double sum = 0;
        int count = 0;
        for (std::size_t i = 0; i < snap.id.size(); ++i)
            if (snap.type[i] == 0 && std::abs(snap.position[3 * i + 2] - z) < 0.5 * s.dp) {
                sum += snap.pressure[i];
                ++count;
            }
        EXPECT_GT(count, 10);
        return sum / count;
    };
    const double rho_g = s.params.rho0 * 9.81;
    // The gradient is rho g; the level sits about 50 Pa low, a known effect of delta-SPH
    // diffusing the density deficit of the truncated kernel at the free surface downwards.
    const double gradient = (mean_pressure_at(0.15) - mean_pressure_at(0.05)) / 0.1;
    EXPECT_NEAR(gradient, rho_g, 0.02 * rho_g);
    const double depth = 0.2 - 0.5 * s.dp;  // the bottom fluid layer: rho g H
    EXPECT_NEAR(mean_pressure_at(depth), rho_g * depth, 0.04 * rho_g * depth);
}

TEST(Precision, ShiftingTheSceneFarFromTheOriginGivesTheSameMotion) {
    const Scene base = test::small_dambreak("0.04");
    Scene far = base;
    const double shift = 1e4 * base.dp;
    for (auto& p : far.position) p = {p[0] + shift, p[1] + shift, p[2] + shift};
    for (int k = 0; k < 3; ++k) {
        far.lo[k] += shift;
        far.hi[k] += shift;
    }
    Simulation a(base, SolverOptions{}), b(far, SolverOptions{});
    test::step_both(a, b, 60);
    const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
    const double worst = test::largest_fluid_difference(pa, pb, base.n_boundary, shift);
    const double moved = test::largest_fluid_difference(base.position, pa, base.n_boundary);
    EXPECT_GT(moved, 0.01 * base.dp);  // the scene did move
    // float32 absolute positions at 1e4 spacings would be off by ~1e-3 dp per rounding.
    EXPECT_LT(worst, 1e-5 * base.dp);
}

TEST(Failure, BlowUpIsCaughtWithinAStepNamingStepAndParticle) {
    const Scene s = test::small_dambreak("0.05");
    SolverOptions opt;
    opt.fixed_dt = 0.02;  // far beyond the CFL limit
    Simulation sim(s, opt);
    try {
        for (int k = 0; k < 200; ++k) sim.step();
        FAIL() << "the run should have blown up";
    } catch (const BlowUpError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("blew up at step"), std::string::npos) << msg;
        EXPECT_NE(msg.find("particle"), std::string::npos) << msg;
        ASSERT_EQ(e.last_good.id.size(), s.size());
        for (double x : e.last_good.position) EXPECT_TRUE(std::isfinite(x) || std::isnan(x));
        for (float v : e.last_good.velocity) ASSERT_TRUE(std::isfinite(v)) << "the last good state must be finite";
    }
}

TEST(Failure, ParticlesLeavingTheDomainAreCountedNotFatal) {
    Scene s = test::random_scene(500, 0, 0.1, 0.01, 3u, 0.0);
    for (auto& v : s.velocity) v = {2.0f, 0.0f, 0.0f};  // everything streams out through +x
    SolverOptions opt;
    opt.fixed_dt = 1e-3;
    Simulation sim(s, opt);
    std::size_t out = 0;
    for (int k = 0; k < 80; ++k) out = sim.step().out_of_domain;
    EXPECT_GT(out, 100u);
    EXPECT_LE(out, s.size());
}

TEST(Failure, UnknownSceneAndOptionAreRefusedByName) {
    try {
        make_scene("teapot", {});
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("teapot"), std::string::npos);
    }
    try {
        make_scene("tank", {{"colour", "blue"}});
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("colour"), std::string::npos);
    }
    EXPECT_THROW(make_scene("tank", {{"dp", "-1"}}), InputError);
    EXPECT_THROW(make_scene("tank", {{"dp", "abc"}}), InputError);
}

}  // namespace
}  // namespace sph
