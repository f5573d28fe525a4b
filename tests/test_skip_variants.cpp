// The variants that skip_bench measures against must give the same motion as the default
// path: integrating boundary particles under their zero acceleration, and a grid over the
// particles' bounding box instead of the scene's domain.
#include <gtest/gtest.h>

#include "backend/subdomain.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

TEST(SkipVariants, GridOverTheParticlesBoundingBoxHasFewerCellsAndTheSameMotion) {
    const Scene s = make_scene("dsph-dambreak", {{"dp", "0.03"}});
    SolverOptions fitted;
    fitted.grid_fits_particles = true;
    Simulation a(s, SolverOptions{}), b(s, fitted);
    EXPECT_LT(b.grid().view.cell_count(), a.grid().view.cell_count());
    test::step_both(a, b, 40);
    const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
    // Only the cell origin differs: float rounding of the cell-relative offsets.
    EXPECT_LT(test::largest_fluid_difference(pa, pb, s.n_boundary), 1e-4 * s.dp);
    EXPECT_GT(test::largest_fluid_difference(s.position, pa, s.n_boundary), 1e-3 * s.dp);  // it moved
}

TEST(SkipVariants, IntegratingBoundaryParticlesUnderZeroAccelerationChangesNothing) {
    const Scene s = test::small_dambreak("0.05");
    const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, 1);
    auto run = [&](bool integrate_boundary) {
        SubdomainConfig cfg{s.params, g.view, s.kernel, true, SearchOptions{}};
        cfg.integrate_boundary = integrate_boundary;
        auto sub = make_host_subdomain(cfg, s.size());
        sub->upload(make_particle_arrays(s, g));
        sub->sort_by_cell();
        sub->advance(euler_step(0));
        for (int k = 0; k < 30; ++k) {
            sub->compute_forces();
            sub->advance(k == 0 ? euler_step(real(1e-4)) : verlet_step(real(1e-4), real(1e-4)));
            sub->sort_by_cell();
        }
        return sub->download();
    };
    const ParticleArrays a = run(false), b = run(true);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a.id[i], b.id[i]);
        ASSERT_EQ(a.cell[i], b.cell[i]);
        EXPECT_EQ(a.pos[i].x, b.pos[i].x);
        EXPECT_EQ(a.pos[i].z, b.pos[i].z);
        EXPECT_EQ(a.velrho[i].w, b.velrho[i].w);
    }
}

}  // namespace
}  // namespace sph
