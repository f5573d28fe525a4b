// The CUDA backend against the host backend: same scene, same steps, same particles. Needs a
// GPU, so CI (which has none) skips it; run it on a GPU machine with tools/gpu-run.sh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "multi/rank_staging.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

// The staging of MPI runs (multi/cuda_rank_staging.cu) without MPI: pieces of a GPU subdomain's
// sorted particles reach pinned host memory bitwise, and pieces unpacked into pinned memory
// reach its receive area at their offsets, ready for the subdomain's next work.
TEST(CudaBackend, PinnedRankStagingCarriesPiecesBitwise) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.05");
    const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, 1, s.periodic.data());
    const SubdomainConfig cfg{s.params, g.view, s.kernel, true, SearchOptions{}};
    std::vector<std::unique_ptr<Subdomain>> subs;
    subs.push_back(make_cuda_subdomain(cfg, 2 * s.size(), 0));
    subs[0]->upload(make_particle_arrays(s, g));
    subs[0]->sort_by_cell();
    const ParticleArrays before = subs[0]->download();
    ASSERT_GT(before.size(), 600u);
    auto same = [](const ParticleSpan& span, const ParticleArrays& a, std::size_t at) {
        const std::size_t n = span.count;
        return std::memcmp(span.pos, &a.pos[at], n * sizeof(real4)) == 0 &&
               std::memcmp(span.velrho, &a.velrho[at], n * sizeof(real4)) == 0 &&
               std::memcmp(span.velrho_prev, &a.velrho_prev[at], n * sizeof(real4)) == 0 &&
               std::memcmp(span.cell, &a.cell[at], n * 4) == 0 && std::memcmp(span.id, &a.id[at], n * 4) == 0;
    };
    const auto staging = make_rank_staging(RankTransport::staged_pinned, subs);
    const std::vector<StagedPiece> out_pieces = {{0, 10, 100}, {0, 500, 50}};
    const std::vector<ParticleSpan> out = staging->stage_out(subs, out_pieces);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].device, -1);
    EXPECT_TRUE(same(out[0], before, 10));
    EXPECT_TRUE(same(out[1], before, 500));
    // Back in, swapped: [500, 550) to the area's start, [10, 110) after it.
    const std::vector<ParticleSpan> areas = {subs[0]->receive_area(150)};
    const std::vector<StagedPiece> in_pieces = {{0, 0, 50}, {0, 50, 100}};
    const std::vector<ParticleSpan> in = staging->stage_in(in_pieces, areas);
    ASSERT_EQ(in.size(), 2u);
    ParticleArrays expected;
    for (const auto& [at, n] : {std::pair<std::size_t, std::size_t>{500, 50}, {10, 100}}) {
        expected.pos.insert(expected.pos.end(), &before.pos[at], &before.pos[at] + n);
        expected.velrho.insert(expected.velrho.end(), &before.velrho[at], &before.velrho[at] + n);
        expected.velrho_prev.insert(expected.velrho_prev.end(), &before.velrho_prev[at], &before.velrho_prev[at] + n);
        expected.cell.insert(expected.cell.end(), &before.cell[at], &before.cell[at] + n);
        expected.id.insert(expected.id.end(), &before.id[at], &before.id[at] + n);
    }
    for (int i = 0; i < 2; ++i) {
        const ParticleSpan& src = out[1 - i];
        const ParticleSpan& dst = in[i];
        std::memcpy(dst.pos, src.pos, src.count * sizeof(real4));
        std::memcpy(dst.velrho, src.velrho, src.count * sizeof(real4));
        std::memcpy(dst.velrho_prev, src.velrho_prev, src.count * sizeof(real4));
        std::memcpy(dst.cell, src.cell, src.count * 4);
        std::memcpy(dst.id, src.id, src.count * 4);
    }
    staging->deliver_in(subs, in_pieces, areas);
    subs[0]->accept_received();  // on the subdomain's stream, ordered after the copies
    const ParticleArrays after = subs[0]->download();
    ASSERT_EQ(after.size(), before.size() + 150);
    EXPECT_TRUE(same({expected.pos.data(), expected.velrho.data(), expected.velrho_prev.data(), expected.cell.data(),
                      expected.id.data(), 150, -1, nullptr},
                     after, before.size()));
}

// Each implementation variant (backend/implementation_variants.hpp) against the host reference:
// the default, then every other value of each variant with the rest at their defaults.
struct VariantCase {
    std::string label;
    ImplementationVariants variants;
};

std::vector<VariantCase> variant_cases() {
    std::vector<VariantCase> cases = {{"defaults", {}}};
    for (const ImplementationVariant& e : implementation_variant_registry())
        for (const std::string& value : e.values) {
            if (value == e.fallback()) continue;
            VariantCase c{std::string(e.name) + "_" + value, {}};
            std::replace(c.label.begin(), c.label.end(), '-', '_');
            set_implementation_variant(c.variants, e.name, value);
            cases.push_back(c);
        }
    return cases;
}

class CudaVariants : public ::testing::TestWithParam<VariantCase> {};

TEST_P(CudaVariants, MatchTheHostBackendAfterNSteps) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    // Then Verlet lists (the listed loop; on the GPU a wall lists fluid only, and the entries
    // carry the rebuild's cell offsets unless list_entries = plain), built on cells of the
    // support, on merged half cells and on merged thirds (the widest stencil those entries take).
    for (const SearchOptions search : {SearchOptions{1, false}, SearchOptions{2, true}, SearchOptions{1, false, true},
                                       SearchOptions{2, true, true}, SearchOptions{3, true, true}}) {
        SolverOptions host, cuda;
        host.search = cuda.search = search;
        host.fixed_dt = cuda.fixed_dt = 1.4e-4;  // the scene's CFL step
        cuda.backend = BackendKind::cuda;
        cuda.variants = GetParam().variants;
        Simulation a(s, host), b(s, cuda);
        const int steps = 400;
        test::step_both(a, b, steps);
        const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
        const double worst = test::largest_fluid_difference(pa, pb, s.n_boundary);
        const double moved = test::largest_fluid_difference(s.position, pa, s.n_boundary);
        // Same summation order on both; only fused multiply-adds on the GPU round differently.
        std::printf("cuda vs host, n = %d, merge = %d, verlet = %d, %d steps (%s): largest position difference %.3g "
                    "dp (largest displacement %.3g dp)\n",
                    search.cells_per_support, int(search.merge), int(search.verlet), steps,
                    describe_implementation_variants(cuda.variants).c_str(), worst / s.dp, moved / s.dp);
        EXPECT_GT(moved, 0.1 * s.dp);
        EXPECT_LT(worst, 1e-3 * s.dp);
    }
}

// A variant that changes only how the GPU stores the same lists gives the default's particles
// bit for bit: list_build = per-lane (build_particle_list, the host's build) and in-step build
// the same entries in the same order as the default's warp per cell (changes 9 and 22 of
// docs/force-loop-notes.md).
// (The other variants change the sums' arithmetic or order: the test above holds them to the host.)
TEST(CudaBackend, ListBuildVariantsMatchTheDefaultBitwise) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    for (const ListBuildVariant build : {ListBuildVariant::per_lane, ListBuildVariant::in_step}) {
        ImplementationVariants v;
        v.list_build = build;
        // Half cells unmerged too: the benchmarks' lists (--verlet --cells-per-support 2);
        // thirds take the in-step build under auto (49 columns).
        for (const SearchOptions search : {SearchOptions{1, false, true}, SearchOptions{2, false, true},
                                           SearchOptions{2, true, true}, SearchOptions{3, true, true}}) {
            SolverOptions base, variant;
            base.backend = variant.backend = BackendKind::cuda;
            base.search = variant.search = search;
            base.fixed_dt = variant.fixed_dt = 1.4e-4;
            variant.variants = v;
            Simulation a(s, base), b(s, variant);
            test::step_both(a, b, 200);
            const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
            std::size_t differ = 0;
            for (std::size_t i = 0; i < pa.size(); ++i) differ += pa[i] != pb[i];
            std::printf("cuda, %s against the defaults, n = %d, merge = %d, Verlet lists, 200 steps: %zu particles "
                        "differ\n",
                        describe_implementation_variants(v).c_str(), search.cells_per_support, int(search.merge),
                        differ);
            EXPECT_EQ(differ, 0u);
        }
    }
}

// A subdomain of the scene with its Verlet lists built by `build` (on the host: its one build).
std::unique_ptr<Subdomain> subdomain_with_lists(const Scene& s, const Grid& g, const SearchOptions& search, bool cuda,
                                                ListBuildVariant build) {
    SubdomainConfig cfg{s.params, g.view, s.kernel, true, search};
    cfg.variants.list_build = build;
    auto d = cuda ? make_cuda_subdomain(cfg, s.size(), 0) : make_host_subdomain(cfg, s.size());
    d->upload(make_particle_arrays(s, g));
    d->sort_by_cell();
    d->advance(euler_step(0));
    d->build_neighbour_list(real(search.skin) * s.params.support);
    return d;
}

// The builds on fresh random clouds with walls, open and periodic in x and y (the warp per
// cell wraps its columns there; a periodic z takes the in-step build): the listed forces of
// each build bitwise the per-lane build's, and within rounding the host backend's (whose
// lists are brute force's within the support: test_neighbours.cpp).
TEST(CudaBackend, ListBuildsGiveTheSameForcesOnRandomClouds) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    for (const bool periodic : {false, true}) {
        Scene s = test::random_scene(3000, 600, 0.3, 0.02, periodic ? 17u : 23u, periodic ? 0.0 : 0.04, 0.5);
        if (periodic) s.periodic = {true, true, false};
        for (const SearchOptions search :
             {SearchOptions{1, false, true}, SearchOptions{2, false, true}, SearchOptions{2, true, true}}) {
            const Grid g = make_grid(s.lo.data(), s.hi.data(), search_reach(s.params.support, search),
                                     search.cells_per_support, s.periodic.data());
            auto forces = [&](bool cuda, ListBuildVariant build) {
                auto d = subdomain_with_lists(s, g, search, cuda, build);
                d->compute_forces_listed();
                const ParticleArrays a = d->download();
                std::vector<real4> by_id(a.id.size());
                for (std::size_t i = 0; i < a.id.size(); ++i) by_id[a.id[i]] = a.force[i];
                return by_id;
            };
            const auto reference = forces(true, ListBuildVariant::per_lane), host = forces(false, {});
            for (const ListBuildVariant build : {ListBuildVariant::automatic, ListBuildVariant::in_step}) {
                const auto f = forces(true, build);
                ASSERT_EQ(f.size(), reference.size());
                std::size_t differ = 0;
                for (std::size_t i = 0; i < f.size(); ++i)
                    differ += std::memcmp(&f[i], &reference[i], sizeof(real4)) != 0;
                EXPECT_EQ(differ, 0u) << "list_build " << int(build) << ", periodic " << periodic << ", n = "
                                      << search.cells_per_support << ", merge = " << search.merge;
            }
            double err = 0, norm = 0;
            for (std::size_t i = 0; i < host.size(); ++i) {
                const double e[4] = {host[i].x - reference[i].x, host[i].y - reference[i].y,
                                     host[i].z - reference[i].z, host[i].w - reference[i].w};
                for (double x : e) err += x * x;
                norm += double(host[i].x) * host[i].x + double(host[i].y) * host[i].y +
                        double(host[i].z) * host[i].z + double(host[i].w) * host[i].w;
            }
            EXPECT_GT(norm, 0.0);
            EXPECT_LT(std::sqrt(err / norm), 1e-5) << "periodic " << periodic << ", n = " << search.cells_per_support;
        }
    }
}

// The lists themselves, not only the forces they give: an entry dropped or added in the skin
// band (support to support + skin) changes no force at the rebuild, and would show in the
// particles only once that pair closed in. On fresh random clouds with walls, open and
// periodic in x and y, every GPU build stores, particle by particle, the host build's entries
// in the host's order (the host's lists are brute force's: test_neighbours.cpp), except that
// on the GPU a wall lists fluid only. The seed is printed, to run a failure again.
TEST(CudaBackend, ListBuildsStoreTheHostsEntries) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const unsigned seed = std::random_device{}();
    std::printf("ListBuildsStoreTheHostsEntries: seed %u\n", seed);
    for (const bool periodic : {false, true}) {
        Scene s = test::random_scene(3000, 600, 0.3, 0.02, seed + unsigned(periodic), periodic ? 0.0 : 0.04, 0.5);
        if (periodic) s.periodic = {true, true, false};
        for (const SearchOptions search :
             {SearchOptions{1, false, true}, SearchOptions{2, false, true}, SearchOptions{2, true, true}}) {
            const Grid g = make_grid(s.lo.data(), s.hi.data(), search_reach(s.params.support, search),
                                     search.cells_per_support, s.periodic.data());
            // Each list as particle ids, in its stored order.
            auto lists = [&](bool cuda, ListBuildVariant build) {
                auto d = subdomain_with_lists(s, g, search, cuda, build);
                const ParticleArrays a = d->download();
                const Subdomain::StoredLists stored = d->download_neighbour_lists();
                std::vector<std::vector<std::uint32_t>> by_id(a.id.size());
                EXPECT_EQ(stored.first.size(), a.id.size() + 1);
                for (std::size_t i = 0; i + 1 < stored.first.size() && i < a.id.size(); ++i)
                    for (std::uint32_t k = stored.first[i]; k < stored.first[i + 1]; ++k)
                        by_id[a.id[i]].push_back(a.id[stored.index[k]]);
                return by_id;
            };
            auto host = lists(false, {});
            std::size_t entries = 0;
            for (std::size_t id = 0; id < host.size(); ++id) {
                if (id < s.n_boundary)  // the GPU's walls list fluid only
                    std::erase_if(host[id], [&](std::uint32_t j) { return j < s.n_boundary; });
                std::sort(host[id].begin(), host[id].end());
                entries += host[id].size();
            }
            EXPECT_GT(entries, 20 * host.size()) << "the clouds should be dense enough to list many neighbours";
            const auto reference = lists(true, ListBuildVariant::per_lane);
            for (const ListBuildVariant build :
                 {ListBuildVariant::per_lane, ListBuildVariant::automatic, ListBuildVariant::in_step}) {
                const auto gpu = build == ListBuildVariant::per_lane ? reference : lists(true, build);
                ASSERT_EQ(gpu.size(), host.size());
                std::size_t differ_host = 0, differ_order = 0;
                for (std::size_t id = 0; id < host.size(); ++id) {
                    differ_order += gpu[id] != reference[id];
                    auto sorted = gpu[id];
                    std::sort(sorted.begin(), sorted.end());
                    differ_host += sorted != host[id];
                }
                std::printf("list_build %d, periodic %d, n = %d, merge = %d: of %zu lists (%zu entries) %zu hold "
                            "other neighbours than the host's, %zu another order than per-lane's\n",
                            int(build), int(periodic), search.cells_per_support, int(search.merge), host.size(),
                            entries, differ_host, differ_order);
                EXPECT_EQ(differ_host, 0u) << "seed " << seed;
                EXPECT_EQ(differ_order, 0u) << "seed " << seed;
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Registry, CudaVariants, ::testing::ValuesIn(variant_cases()),
                         [](const auto& info) { return info.param.label; });

// The gauge kernels (cuda_gauges.cu) against the host's loops on the same run: a collapsing
// column read by every kind of gauge, with the cell search and with Verlet lists (particles
// then stray from the cells of the last sort).
TEST(CudaBackend, GaugesMatchTheHostBackend) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    auto gauge = [](GaugeKind kind, const char* name, double x, double y, double z) {
        Gauge g = test::gauge_at(kind, name, x, y, z);
        g.radius = 0.05;
        g.body = "tank";
        return g;
    };
    const std::vector<Gauge> gauges = {gauge(GaugeKind::water_level, "level", 0.2, 0.1, 0),
                                       gauge(GaugeKind::pressure, "p", 0.2, 0.1, 0.05),
                                       gauge(GaugeKind::velocity, "v", 0.4, 0.1, 0.05),
                                       gauge(GaugeKind::max_height, "top", 0.3, 0.1, 0),
                                       gauge(GaugeKind::force, "f", 0, 0, 0)};
    const char* what[] = {"level", "p", "vx", "vy", "vz", "top", "fx", "fy", "fz"};
    for (const SearchOptions search : {SearchOptions{1, false}, SearchOptions{2, true, true}}) {
        SolverOptions host, cuda;
        host.search = cuda.search = search;
        host.fixed_dt = cuda.fixed_dt = 1.4e-4;
        cuda.backend = BackendKind::cuda;
        Simulation a(s, host), b(s, cuda);
        test::step_both(a, b, 200);
        const std::vector<double> va = a.measure_gauges(gauges), vb = b.measure_gauges(gauges);
        ASSERT_EQ(va.size(), 9u);
        ASSERT_EQ(vb.size(), va.size());
        const double weight = double(s.fluid_count()) * s.params.mass * 9.81;
        const double scale[] = {s.dp, 1e3, 1, 1, 1, s.dp, weight, weight, weight};
        for (std::size_t k = 0; k < va.size(); ++k) {
            EXPECT_TRUE(std::isfinite(va[k])) << what[k];
            EXPECT_NEAR(vb[k], va[k], 1e-3 * scale[k]) << what[k] << ", verlet = " << search.verlet;
        }
    }
}

// One subdomain (one) and several (many) run side by side for `steps` steps: the particles of
// many's snapshot, how many differ from one's by id, and what the two runs did.
struct OneAgainstMany {
    std::size_t particles = 0, differ = 0;
    int moved = 0;          // slices the balancer moved in many
    double largest_dp = 0;  // the largest fluid difference, in spacings
    long builds_one = 0, builds_many = 0;  // Verlet list builds
};
OneAgainstMany run_one_against_many(const Scene& s, const SolverOptions& one, const SolverOptions& many, int steps) {
    Simulation a(s, one), b(s, many);
    OneAgainstMany r;
    for (int k = 0; k < steps; ++k) {
        a.step();
        r.moved += b.step().slices_moved;
    }
    const SnapshotData sb = b.snapshot();
    r.particles = sb.id.size();
    if (r.particles != s.size()) return r;
    const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(sb);
    for (std::size_t i = 0; i < pa.size(); ++i) r.differ += pa[i] != pb[i];
    r.largest_dp = test::largest_fluid_difference(pa, pb, s.n_boundary) / s.dp;
    r.builds_one = a.neighbour_list_builds();
    r.builds_many = b.neighbour_list_builds();
    return r;
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
        const OneAgainstMany r = run_one_against_many(s, one, many, 200);
        ASSERT_EQ(r.particles, s.size()) << "particles lost or duplicated";
        std::printf("cuda, 4 subdomains on one GPU (balancer %s, %d slices moved) vs 1, 200 steps: %zu particles "
                    "differ, largest difference %.3g dp\n",
                    balancer, r.moved, r.differ, r.largest_dp);
        EXPECT_EQ(r.differ, 0u) << balancer;
    }
}

// Verlet lists on several subdomains sharing one GPU (issue 25, step 7 of
// docs/lists-with-slabs.md): between rebuilds each ghost block is refreshed in place from its
// owner (with cell offsets in the entries, the owner's list frame; with plain entries, the
// cells, whose coordinates the receiver recomputes), through each transport that works on one
// GPU, overlapped and not; the rebuilds repartition. Against one subdomain with lists: the
// same particles, bitwise, and the same rebuilds.
TEST(CudaBackend, ListsOnSeveralSubdomainsOnOneGpuMatchOneBitwise) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    for (const ListEntriesVariant entries : {ListEntriesVariant::automatic, ListEntriesVariant::plain})
        for (const TransportKind transport : {TransportKind::peer, TransportKind::staged})
            for (const bool overlap : {false, true}) {
                SolverOptions one, many;
                one.backend = many.backend = BackendKind::cuda;
                one.fixed_dt = many.fixed_dt = 1.4e-4;
                one.search = many.search = SearchOptions{2, true, true, 0.1, 5};
                one.variants.list_entries = many.variants.list_entries = entries;
                many.subdomains = 4;
                many.device_map = {0, 0, 0, 0};
                many.balancer = "simple";
                many.transport = transport;
                many.overlap = overlap;
                const OneAgainstMany r = run_one_against_many(s, one, many, 200);
                ASSERT_EQ(r.particles, s.size()) << "particles lost or duplicated";
                const char* layout = entries == ListEntriesVariant::plain ? "plain" : "cell offsets";
                std::printf("cuda lists (%s), 4 subdomains on one GPU, transport %s, overlap %s (%ld builds, %d slices "
                            "moved) vs 1, 200 steps: %zu particles differ, largest difference %.3g dp\n",
                            layout, transport_label(transport), overlap ? "on" : "off", r.builds_many, r.moved,
                            r.differ, r.largest_dp);
                EXPECT_EQ(r.differ, 0u) << layout << ", " << transport_label(transport) << ", overlap " << overlap;
                EXPECT_EQ(r.builds_one, r.builds_many);
                EXPECT_GT(r.moved, 0);
            }
}

// Paper section 5.3 on the GPU: the boundary slices updated first and copied on the
// transport's own streams while the inner slices are updated. Several subdomains sharing one
// GPU with the overlap on and off, and one subdomain, give bitwise the same particles, for
// each transport that works on one GPU, without and with a balancer moving slices (whose
// move then travels with the boundary slices).
TEST(CudaBackend, SeveralSubdomainsOnOneGpuOverlapOnAndOffMatchBitwise) {
    if (!cuda_backend_available()) GTEST_SKIP() << "no CUDA GPU on this machine (CI has none)";
    const Scene s = test::small_dambreak("0.02");
    for (const TransportKind transport : {TransportKind::peer, TransportKind::staged})
        for (const char* balancer : {"none", "simple"}) {
            SolverOptions one, off, on;
            one.backend = off.backend = on.backend = BackendKind::cuda;
            one.fixed_dt = off.fixed_dt = on.fixed_dt = 1.4e-4;
            off.subdomains = on.subdomains = 4;
            off.device_map = on.device_map = {0, 0, 0, 0};
            off.balancer = on.balancer = balancer;
            off.transport = on.transport = transport;
            off.overlap = false;
            on.overlap = true;
            Simulation a(s, one), b(s, off), c(s, on);
            int moved = 0;
            unsigned long long migrated = 0;
            for (int k = 0; k < 200; ++k) {
                a.step();
                b.step();
                const StepRecord& r = c.step();
                moved += r.slices_moved;
                migrated += r.exchange.particles_migrated;
            }
            const SnapshotData sc = c.snapshot();
            ASSERT_EQ(sc.id.size(), s.size()) << "particles lost or duplicated";
            const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot()),
                       pc = test::positions_by_id(sc);
            std::size_t differ_off = 0, differ_one = 0;
            for (std::size_t i = 0; i < pc.size(); ++i) {
                differ_off += pb[i] != pc[i];
                differ_one += pa[i] != pc[i];
            }
            std::printf("cuda, 4 subdomains on one GPU, overlap on (transport %s, balancer %s, %d slices moved, %llu "
                        "migrated), 200 steps: %zu particles differ from overlap off, %zu from one subdomain\n",
                        c.transport_name().c_str(), balancer, moved, migrated, differ_off, differ_one);
            EXPECT_EQ(differ_off, 0u) << transport_label(transport) << ", " << balancer;
            EXPECT_EQ(differ_one, 0u) << transport_label(transport) << ", " << balancer;
            if (std::string(balancer) != "none") {
                EXPECT_GT(moved, 0);
            }
        }
}

// The same across GPUs where there are two or more (one subdomain each, every transport):
// the copy streams of two GPUs against the order without overlap.
TEST(CudaBackend, OverlapOnAndOffMatchBitwiseAcrossGpus) {
    if (cuda_device_count() < 2) GTEST_SKIP() << "needs two GPUs";
    const Scene s = test::small_dambreak("0.02");
    for (const TransportKind transport : {TransportKind::automatic, TransportKind::staged, TransportKind::nccl}) {
        SolverOptions off, on;
        off.backend = on.backend = BackendKind::cuda;
        off.fixed_dt = on.fixed_dt = 1.4e-4;
        off.subdomains = on.subdomains = 2;
        off.device_map = on.device_map = {0, 1};
        off.balancer = on.balancer = "simple";
        off.transport = on.transport = transport;
        off.overlap = false;
        Simulation b(s, off), c(s, on);
        test::step_both(b, c, 200);
        const auto pb = test::positions_by_id(b.snapshot()), pc = test::positions_by_id(c.snapshot());
        std::size_t differ = 0;
        for (std::size_t i = 0; i < pc.size(); ++i) differ += pb[i] != pc[i];
        std::printf("cuda, 2 GPUs, transport %s, overlap on vs off, 200 steps: %zu particles differ\n",
                    c.transport_name().c_str(), differ);
        EXPECT_EQ(differ, 0u) << transport_label(transport);
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
