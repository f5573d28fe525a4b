// The Taylor-Green vortex against its exact decay: the scene starts on the exact solution,
// a short run stays close to it, and the check is sharp enough to catch a wrong viscosity.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/error.hpp"
#include "test_support.hpp"
#include "validation/taylor_green.hpp"

namespace sph {
namespace {

TaylorGreenError run_taylor_green(const Scene& run, const Scene& judged_against, double t_end) {
    Simulation sim(run, SolverOptions{});
    while (sim.time() < t_end) sim.step();
    return taylor_green_error(sim.snapshot(), judged_against);
}

TEST(TaylorGreen, SceneStartsOnTheExactSolution) {
    const Scene s = make_scene("taylor-green", {{"resolution", "16"}});
    EXPECT_EQ(s.size(), 16u * 16u * 4u);
    EXPECT_EQ(s.periodic, (std::array<bool, 3>{true, true, true}));
    EXPECT_NEAR(double(s.params.nu), 0.01, 1e-9);  // Re 100 with U = 1 m/s and a 1 m wavelength
    Simulation sim(s, SolverOptions{});
    const TaylorGreenError e = taylor_green_error(sim.snapshot(), sim.scene());
    EXPECT_LT(e.velocity_l2, 1e-6);
    EXPECT_LT(e.energy_decay_error, 1e-6);  // the lattice holds exactly M U^2 / 4
}

TEST(TaylorGreen, OptionsAreStrict) {
    EXPECT_THROW(make_scene("taylor-green", {{"reynolds", "50"}, {"nu", "0.01"}}), InputError);
    EXPECT_THROW(make_scene("taylor-green", {{"gravity", "9.81"}}), InputError);
    EXPECT_THROW(make_scene("taylor-green", {{"resolution", "16"}, {"layers", "2"}}), InputError);  // z under the support
    EXPECT_THROW(taylor_green_error(SnapshotData{}, make_scene("tank", {})), InputError);
    SolverOptions lists;  // shifting's gradient pass needs sorted cells every step
    lists.search.verlet = true;
    EXPECT_THROW(Simulation(make_scene("taylor-green", {{"resolution", "16"}, {"layers", "8"}}), lists), InputError);
    lists.search.verlet = false;
    EXPECT_NO_THROW(Simulation(make_scene("taylor-green", {{"resolution", "16"}, {"layers", "8"}}), lists));
}

// Measured at resolution 24, Re 20, t = 0.1 s (a third of the velocity's e-folding time), the
// Verlet scheme of commit 51c577b: velocity_l2 0.0150, energy error 0.0271 (resolution 16:
// 0.025, 0.049; 32: 0.011, 0.019; 64: 0.0075, 0.013; the kick-drift-kick scheme before it:
// 0.0185 and 0.031 at 24). The bounds leave about 2.5x room. The same run with nu off by 2x
// (Re 10 or 40) scored velocity_l2 0.31 or 0.23 against Re 20 (kick-drift-kick; the test
// asserts above 0.04 with either scheme): the exact decay
// exp(-2 nu k^2 t) moves by 20-30% there, so a wrong viscosity cannot pass.
TEST(TaylorGreen, ShortRunFollowsTheExactDecay) {
    const std::map<std::string, std::string> base = {{"resolution", "24"}, {"reynolds", "20"}};
    const Scene s = make_scene("taylor-green", base);
    const TaylorGreenError e = run_taylor_green(s, s, 0.1);
    std::printf("measured velocity_l2 %.4f, energy_decay_error %.4f\n", e.velocity_l2, e.energy_decay_error);
    EXPECT_LT(e.velocity_l2, 0.04);
    EXPECT_LT(e.energy_decay_error, 0.065);
    for (const char* wrong_re : {"10", "40"}) {
        auto opts = base;
        opts["reynolds"] = wrong_re;
        const TaylorGreenError w = run_taylor_green(make_scene("taylor-green", opts), s, 0.1);
        EXPECT_GT(w.velocity_l2, 0.04) << "Re " << wrong_re << " passed for Re 20";
    }
}

}  // namespace
}  // namespace sph

namespace sph {
namespace {

// The convergence table of the report (not run by default; about a minute of CPU):
//   build-p/tests/sph_tests --gtest_also_run_disabled_tests --gtest_filter='TaylorGreen.DISABLED_*'
TEST(TaylorGreen, DISABLED_ErrorAtThreeResolutions) {
    for (const char* re : {"100", "20"})
        for (const char* res : {"16", "32", "64"}) {
            const Scene s = make_scene("taylor-green", {{"resolution", res}, {"reynolds", re}});
            const TaylorGreenError e = run_taylor_green(s, s, 0.1);
            std::printf("Re %3s  resolution %2s  t 0.1 s  velocity_l2 %.4f  energy_decay_error %.4f\n", re, res,
                        e.velocity_l2, e.energy_decay_error);
        }
}

}  // namespace
}  // namespace sph

namespace sph {
namespace {

// Past a third of the decay time the lattice, stretched at the vortices' stagnation points,
// breaks the kernel sums: without shifting the velocity error of a Re 100 run jumps from 0.5%
// at 0.1 s to 7% at 0.15 s and 30-40% by 0.3 s (resolution 32, host). Shifting holds it:
// measured here (resolution 16, t = 0.3 s) 0.056 with the scene's default shifting, 0.41
// without.
TEST(TaylorGreen, ShiftingKeepsALongRunOnTheExactDecay) {
    const Scene shifted = make_scene("taylor-green", {{"resolution", "16"}});
    const Scene plain = make_scene("taylor-green", {{"resolution", "16"}, {"shifting", "0"}});
    ASSERT_GT(double(shifted.params.shift), 0);  // on by default for this scene
    const TaylorGreenError with = run_taylor_green(shifted, shifted, 0.3);
    const TaylorGreenError without = run_taylor_green(plain, plain, 0.3);
    std::printf("measured at t = 0.3 s: velocity_l2 %.4f with shifting, %.4f without\n", with.velocity_l2,
                without.velocity_l2);
    EXPECT_LT(with.velocity_l2, 0.1);
    EXPECT_GT(without.velocity_l2, 0.15);
}

}  // namespace
}  // namespace sph
