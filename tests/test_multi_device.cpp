// N subdomains (X slabs with ghosts, migration and load balancing) against one subdomain.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

#include "backend/key_order.hpp"

#include "test_support.hpp"

namespace sph {
namespace {

void expect_each_particle_once(const SnapshotData& s, std::size_t total, long step) {
    std::set<std::uint32_t> ids(s.id.begin(), s.id.end());
    ASSERT_EQ(s.id.size(), total) << "step " << step << ": particles lost or duplicated";
    ASSERT_EQ(ids.size(), total) << "step " << step << ": a particle is held twice";
}

struct MultiCase {
    int subdomains;
    const char* balancer;
    int cells_per_support;
    bool merge;
};

class MultiDevice : public ::testing::TestWithParam<MultiCase> {};

// Ghost slices hold exactly the particles of those cells, sorted by id like everything else,
// so every particle sums its neighbours in the same order as in one subdomain: the result
// is bitwise the same, not just within float tolerance.
TEST_P(MultiDevice, MatchesOneSubdomainBitwise) {
    const MultiCase mc = GetParam();
    const Scene s = test::small_dambreak("0.04");
    SolverOptions one, many;
    one.search = many.search = SearchOptions{mc.cells_per_support, mc.merge};
    many.subdomains = mc.subdomains;
    many.balancer = mc.balancer;
    Simulation a(s, one), b(s, many);
    ASSERT_EQ(b.subdomain_count(), mc.subdomains);
    int moved = 0;
    for (long k = 1; k <= 60; ++k) {
        a.step();
        moved += b.step().slices_moved;
        if (k % 10 == 0) expect_each_particle_once(b.snapshot(), s.size(), k);
    }
    const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < pa.size(); ++i)
        if (pa[i] != pb[i]) ++differ;
    EXPECT_EQ(differ, 0u) << "particles whose position differs from the one-subdomain run";
    EXPECT_DOUBLE_EQ(a.time(), b.time());
    if (std::string(mc.balancer) != "none") {
        EXPECT_GT(moved, 0) << "the balancer never moved a slice";
    }
}

INSTANTIATE_TEST_SUITE_P(Slabs, MultiDevice,
                         ::testing::Values(MultiCase{2, "none", 1, false}, MultiCase{3, "none", 1, true},
                                           MultiCase{4, "simple", 1, true}, MultiCase{2, "threshold", 1, true},
                                           MultiCase{3, "every:5", 2, true}, MultiCase{2, "simple", 2, false},
                                           MultiCase{4, "equal-time", 1, true}),
                         [](const auto& info) {
                             std::string b = info.param.balancer;
                             for (char& c : b)
                                 if (c == ':' || c == '-') c = '_';
                             return std::to_string(info.param.subdomains) + "_" + b + "_n" +
                                    std::to_string(info.param.cells_per_support);
                         });

// The host sort merges a few ascending runs (what an exchange leaves: the kept range and one
// run per sender) instead of sorting; the order must be the full sort's, for 1 to 40 runs
// (past 32 it sorts) and for a shuffled array.
TEST(HostSort, MergingRunsGivesTheFullSortsOrder) {
    std::mt19937 rng(7);
    for (int runs : {1, 2, 3, 5, 17, 32, 33, 40, 0}) {
        std::vector<std::uint64_t> keys;
        if (runs == 0) {  // shuffled
            keys.resize(5000);
            std::iota(keys.begin(), keys.end(), 0);
            std::shuffle(keys.begin(), keys.end(), rng);
        }
        for (int r = 0; r < runs; ++r) {
            std::vector<std::uint64_t> run(1 + rng() % 300);
            for (auto& k : run) k = (std::uint64_t(rng() % 64) << 32) | rng();  // (cell, id)
            std::sort(run.begin(), run.end());
            keys.insert(keys.end(), run.begin(), run.end());
        }
        std::vector<std::uint32_t> order(keys.size()), expected(keys.size());
        std::iota(order.begin(), order.end(), 0u);
        std::iota(expected.begin(), expected.end(), 0u);
        order_by_keys(keys, order);
        std::sort(expected.begin(), expected.end(), [&](auto x, auto y) { return keys[x] < keys[y]; });
        EXPECT_EQ(order, expected) << runs << " runs";
    }
}

TEST(MultiDeviceErrors, TooManySubdomainsForTheGridIsAClearError) {
    SolverOptions o;
    o.subdomains = 500;
    try {
        Simulation sim(test::small_dambreak("0.04"), o);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("500"), std::string::npos) << e.what();
    }
}

TEST(MultiDeviceErrors, GpuTransportsFallBackToHostCopiesOnTheHostAndSaySo) {
    EXPECT_THROW(parse_transport("carrier-pigeon"), InputError);
    for (TransportKind gpu_only : {TransportKind::peer, TransportKind::staged, TransportKind::nccl}) {
        SolverOptions o;
        o.subdomains = 2;
        o.transport = gpu_only;
        Simulation sim(test::small_dambreak("0.04"), o);
        EXPECT_EQ(sim.transport_name(), "host");
        EXPECT_NE(sim.transport_note().find(transport_label(gpu_only)), std::string::npos) << sim.transport_note();
    }
}

// Every transfer is counted once: bytes are the particles received times their size, and a
// run without balancing migrates only particles that crossed a slab boundary.
TEST(MultiDeviceErrors, ExchangeCountersAddUp) {
    SolverOptions o;
    o.subdomains = 3;
    Simulation sim(test::small_dambreak("0.04"), o);
    EXPECT_EQ(sim.transport_name(), "host");
    for (int k = 0; k < 20; ++k) {
        const StepRecord& r = sim.step();
        EXPECT_GT(r.exchange.ghosts_sent, 0u);
        EXPECT_EQ(r.exchange.bytes,
                  (r.exchange.ghosts_sent + r.exchange.particles_migrated) * exchanged_bytes_per_particle);
    }
}

TEST(MultiDeviceErrors, UnknownBalancerIsRefusedByName) {
    SolverOptions o;
    o.subdomains = 2;
    o.balancer = "greedy";
    EXPECT_THROW(Simulation(test::small_dambreak("0.04"), o), InputError);
}

}  // namespace
}  // namespace sph
