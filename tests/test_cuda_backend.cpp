// The CUDA backend against the host backend: same scene, same steps, same particles. Needs a
// GPU, so CI (which has none) skips it; run it on a GPU machine with tools/gpu-run.sh.
#include <gtest/gtest.h>

#include <cmath>

#include "test_support.hpp"

namespace sph {
namespace {

TEST(CudaBackend, MatchesTheHostBackendAfterNSteps) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    for (const SearchOptions search : {SearchOptions{1, false}, SearchOptions{2, true}}) {
        SolverOptions host, cuda;
        host.search = cuda.search = search;
        host.fixed_dt = cuda.fixed_dt = 1.4e-4;  // the scene's CFL step
        cuda.backend = BackendKind::cuda;
        Simulation a(s, host), b(s, cuda);
        const int steps = 400;
        test::step_both(a, b, steps);
        const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
        const double worst = test::largest_fluid_difference(pa, pb, s.n_boundary);
        const double moved = test::largest_fluid_difference(s.position, pa, s.n_boundary);
        // Same summation order on both; only fused multiply-adds on the GPU round differently.
        std::printf("cuda vs host, n = %d, merge = %d, %d steps: largest position difference %.3g dp "
                    "(largest displacement %.3g dp)\n",
                    search.cells_per_support, int(search.merge), steps, worst / s.dp, moved / s.dp);
        EXPECT_GT(moved, 0.1 * s.dp);
        EXPECT_LT(worst, 1e-3 * s.dp);
    }
}

// Several subdomains sharing one GPU against one subdomain on it: ghosts hold exactly the
// particles of their cells, sorted by id, so each particle sums its neighbours in the same
// order and the result is bitwise the same (as on the host, MultiDevice).
TEST(CudaBackend, SeveralSubdomainsOnOneGpuMatchOneBitwise) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    for (const char* balancer : {"none", "equal-time"}) {
        SolverOptions one, many;
        one.backend = many.backend = BackendKind::cuda;
        one.fixed_dt = many.fixed_dt = 1.4e-4;
        many.subdomains = 4;
        many.device_map = {0, 0, 0, 0};
        many.balancer = balancer;
        Simulation a(s, one), b(s, many);
        int moved = 0;
        for (int k = 0; k < 200; ++k) {
            a.step();
            moved += b.step().slices_moved;
        }
        const SnapshotData sb = b.snapshot();
        ASSERT_EQ(sb.id.size(), s.size()) << "particles lost or duplicated";
        const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(sb);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < pa.size(); ++i) differ += pa[i] != pb[i];
        std::printf("cuda, 4 subdomains on one GPU (balancer %s, %d slices moved) vs 1, 200 steps: %zu particles "
                    "differ, largest difference %.3g dp\n",
                    balancer, moved, differ, test::largest_fluid_difference(pa, pb, s.n_boundary) / s.dp);
        EXPECT_EQ(differ, 0u) << balancer;
    }
}

// Two subdomains on the GPU(s) (one each where there are two) against one on the host, with
// every transport: the particles must not depend on how they travelled.
class CudaTransports : public ::testing::TestWithParam<TransportKind> {};

TEST_P(CudaTransports, TwoSubdomainsMatchTheHostBackend) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    SolverOptions host, cuda;
    host.fixed_dt = cuda.fixed_dt = 1.4e-4;
    cuda.backend = BackendKind::cuda;
    cuda.subdomains = 2;
    cuda.balancer = "threshold";
    cuda.transport = GetParam();
    if (GetParam() == TransportKind::nccl && cuda_device_count() < 2) {
        // NCCL has one rank per GPU: two subdomains on one GPU must be refused clearly.
        EXPECT_THROW(Simulation(s, cuda), InputError);
        GTEST_SKIP() << "the nccl transport needs two GPUs; checked that one GPU is refused";
    }
    Simulation a(s, host), b(s, cuda);
    test::step_both(a, b, 300);
    const SnapshotData sb = b.snapshot();
    ASSERT_EQ(sb.id.size(), s.size()) << "particles lost or duplicated";
    const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(sb);
    const double worst = test::largest_fluid_difference(pa, pb, s.n_boundary);
    std::printf("cuda with 2 subdomains (%s, transport %s) vs host, 300 steps: largest position difference %.3g dp\n",
                b.device_name().c_str(), b.transport_name().c_str(), worst / s.dp);
    EXPECT_LT(worst, 1e-3 * s.dp);
}

INSTANTIATE_TEST_SUITE_P(Exchange, CudaTransports,
                         ::testing::Values(TransportKind::automatic, TransportKind::peer, TransportKind::staged,
                                           TransportKind::nccl),
                         [](const auto& info) { return std::string(transport_label(info.param)); });

}  // namespace
}  // namespace sph
