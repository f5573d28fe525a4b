// Scenes: particle counts hit their targets, DualSPHysics' dam break has its particle counts,
// and the paper's mesh scenes are filled inside their box.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "scenes/scene.hpp"

namespace sph {
namespace {

TEST(Scenes, DualSphysicsDamBreakHasItsParticleCounts) {
    const Scene s = make_scene("dsph-dambreak", {});  // dp = 0.0045 m
    EXPECT_EQ(s.fluid_count(), 882524u);
    // DualSPHysics' GenCase makes 154,240 boundary particles; our lattice walls come close.
    EXPECT_NEAR(double(s.n_boundary), 154240.0, 0.03 * 154240.0);
    EXPECT_NEAR(double(s.params.h), std::sqrt(3.0) * 0.0045, 1e-7);
    EXPECT_NEAR(double(s.params.c0), 20 * std::sqrt(9.81 * 0.3), 1e-4);
    EXPECT_EQ(s.kernel, KernelType::cubic);
}

TEST(Scenes, TargetParticleCountIsHitWithinOnePercent) {
    const std::vector<std::pair<std::string, long long>> cases = {
        {"dambreak", 23456}, {"dambreak", 61000}, {"tank", 50000}, {"tank", 100000}, {"dsph-dambreak", 250000}};
    for (const auto& [name, target] : cases) {
        const Scene s = make_scene(name, {{"particles", std::to_string(target)}});
        EXPECT_NEAR(double(s.fluid_count()), double(target), 0.01 * target) << name;
    }
    // Lattice counts come in steps: a target between two steps is refused, not missed silently.
    EXPECT_THROW(make_scene("dambreak", {{"particles", "5000"}}), InputError);
}

TEST(Scenes, MeshSceneIsFilledInsideItsBox) {
    if (!std::filesystem::exists(std::string(SPH_SOURCE_DIR) + "/../shared/meshes/bunny.obj"))
        GTEST_SKIP() << "the shared meshes are not beside the checkout";
    const Scene s = make_scene("bunny", {{"particles", "20000"}});
    EXPECT_NEAR(double(s.fluid_count()), 20000.0, 200.0);
    for (std::size_t i = 0; i < s.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            ASSERT_GT(s.position[i][k], s.lo[k]);
            ASSERT_LT(s.position[i][k], s.hi[k]);
        }
    // Fluid volume: particles times dp^3 is the mesh volume scaled to height 1 m.
    const double scale = 1.0 / 0.616;  // bunny.obj is 0.616 tall along y
    const double volume = 0.04848 * scale * scale * scale;
    EXPECT_NEAR(double(s.fluid_count()) * s.dp * s.dp * s.dp, volume, 0.02 * volume);
}

TEST(Scenes, BrokenMeshIsRefusedNamingTheFile) {
    const auto dir = std::filesystem::temp_directory_path() / "sph_broken_mesh";
    std::filesystem::create_directories(dir);
    const auto path = (dir / "empty.obj").string();
    { std::ofstream(path) << "# nothing\n"; }
    try {
        make_scene("bunny", {{"mesh", path}, {"particles", "1000"}});
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace sph
