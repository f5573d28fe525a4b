// Cluster lists (neighbours/particle_clusters.hpp, physics/cluster_lists.hpp; change 15 of
// docs/force-loop-notes.md): the pairs inside the support among the particles of a cluster's
// listed clusters are exactly brute force's, on a random cloud and on a flowing dam break; and
// the per-particle lists built from them hold the stencil's build's entries in its order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <set>

#include "physics/cluster_lists.hpp"
#include "physics/dispatch.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

// A sorted state with its cell starts, as a rebuild sees it.
struct SortedState {
    Grid grid;
    PhysicsParams params;
    ParticleArrays a;
    std::vector<std::uint32_t> start;
    std::uint32_t end = 0;  // particles inside the domain: [0, end)
    ForceInputs inputs() const {
        return {a.pos.data(), a.velrho.data(), a.velrho_prev.data(), a.cell.data(), start.data(), nullptr, grid.view,
                nullptr};
    }
};

SortedState sort_scene(const Scene& s, int cells_per_support, double reach) {
    SortedState st{make_grid(s.lo.data(), s.hi.data(), reach, cells_per_support), s.params, {}, {}, 0};
    auto d = make_host_subdomain({s.params, st.grid.view, s.kernel, true, SearchOptions{cells_per_support, false}},
                                 s.size());
    d->upload(make_particle_arrays(s, st.grid));
    d->sort_by_cell();
    st.a = d->download();
    const std::uint32_t ncells = st.grid.view.cell_count();
    st.start.resize(ncells + 1);
    for (std::uint32_t c = 0; c <= ncells; ++c)
        st.start[c] = std::uint32_t(std::lower_bound(st.a.cell.begin(), st.a.cell.end(), c) - st.a.cell.begin());
    st.end = st.start[ncells];
    return st;
}

// Every cluster, its box and its list, as a rebuild makes them.
struct BuiltClusters {
    std::vector<ClusterBox> boxes;
    std::vector<std::uint32_t> index, count, cluster_of, cluster_begin;
    unsigned long long tested = 0;
    std::uint32_t end = 0;
    std::uint32_t clusters() const { return std::uint32_t(boxes.size()); }
    ClusterList list() const {
        return {index.data(), count.data(), clusters(), cluster_of.data(), cluster_begin.data(), end};
    }
};

BuiltClusters build_clusters(const SortedState& st, real reach, std::uint32_t capacity = 600) {
    BuiltClusters b;
    const GridView& g = st.grid.view;
    b.end = st.end;
    const std::uint32_t columns = std::uint32_t(g.nx * g.ny);
    std::vector<std::uint32_t> first(columns + 1, 0);
    for (std::uint32_t col = 0; col < columns; ++col) first[col + 1] = first[col] + column_cluster_count(col, st.start.data(), g.nz);
    const std::uint32_t nc = first[columns];
    b.cluster_begin.assign(nc + 1, st.end);
    b.cluster_of.assign(st.end, ~0u);
    for (std::uint32_t col = 0; col < columns; ++col)
        fill_column_clusters(col, st.start.data(), g.nz, first[col], b.cluster_begin.data(), b.cluster_of.data());
    b.boxes.resize(nc);
    for (std::uint32_t k = 0; k < nc; ++k) {
        EXPECT_LT(b.cluster_begin[k], b.cluster_begin[k + 1]) << "cluster " << k;
        EXPECT_LE(b.cluster_begin[k + 1] - b.cluster_begin[k], cluster_size) << "cluster " << k;
        b.boxes[k] = cluster_box(b.cluster_begin[k], b.cluster_begin[k + 1], st.a.pos.data(), st.a.velrho.data(),
                                 st.a.cell.data(), g);
    }
    for (std::uint32_t i = 0; i < st.end; ++i) {
        const std::uint32_t k = b.cluster_of[i];
        EXPECT_TRUE(k < nc && b.cluster_begin[k] <= i && i < b.cluster_begin[k + 1]) << "particle " << i;
        // A cluster stays in one column.
        if (i > b.cluster_begin[k]) {
            EXPECT_EQ(st.a.cell[i] / std::uint32_t(g.nz), st.a.cell[i - 1] / std::uint32_t(g.nz)) << "particle " << i;
        }
    }
    b.index.assign(std::size_t(capacity) * nc, 0);
    b.count.assign(nc, 0);
    for (std::uint32_t k = 0; k < nc; ++k) {
        const ClusterBuildWork w = build_cluster_list(k, b.boxes.data(), b.cluster_of.data(), st.start.data(), g, reach,
                                                      b.index.data(), nc, capacity);
        EXPECT_LE(w.listed, capacity);
        b.count[k] = std::min(w.listed, capacity);
        b.tested += w.tested;
    }
    return b;
}

// Pairs (by id) whose terms the force loop sums (not both boundary), found by testing every
// pair with the listed loop's arithmetic (the separation from cell-relative offsets).
PairSet brute_force_pairs(const SortedState& st) {
    PairSet pairs;
    const GridView& g = st.grid.view;
    const PhysicsParams& p = st.params;
    for (std::uint32_t i = 0; i < st.end; ++i) {
        const int3v ci = g.decode(st.a.cell[i]);
        for (std::uint32_t j = 0; j < st.end; ++j) {
            if (i == j || (is_boundary(st.a.velrho[i]) && is_boundary(st.a.velrho[j]))) continue;
            const int3v cj = g.decode(st.a.cell[j]);
            const real3 r = separation(st.a.pos[i], st.a.pos[j], cj.x - ci.x, cj.y - ci.y, cj.z - ci.z, g.cell_size);
            const real r2 = dot(r, r);
            if (r2 < p.support2 && r2 > real(1e-18) * p.support2) pairs.insert({st.a.id[i], st.a.id[j]});
        }
    }
    return pairs;
}

// The pairs inside the support among each particle's candidates (every particle of its cluster's
// listed clusters but itself), by id, with the candidates counted and each pair visited at most once.
struct Walked {
    PairSet pairs;
    unsigned long long candidates = 0, neighbours = 0, visits = 0;
};

Walked walk_pairs(const SortedState& st, const BuiltClusters& b) {
    Walked w;
    const GridView& g = st.grid.view;
    const PhysicsParams& p = st.params;
    const ClusterList list = b.list();
    const ForceInputs in = st.inputs();
    for (std::uint32_t i = 0; i < st.end; ++i) {
        const SearchWork work = particle_cluster_work(i, in, list, p);
        w.candidates += work.candidates;
        w.neighbours += work.neighbours;
        const std::uint32_t c = b.cluster_of[i];
        const int3v ci = g.decode(st.a.cell[i]);
        std::uint32_t previous = 0;
        for (std::uint32_t k = 0; k < b.count[c]; ++k) {
            const std::uint32_t cj = b.index[std::size_t(k) * list.stride + c];
            if (k > 0) {
                EXPECT_GT(cj, previous) << "cluster " << c << ": entries ascend, each once";
            }
            previous = cj;
            for (std::uint32_t j = b.cluster_begin[cj]; j < b.cluster_begin[cj + 1]; ++j) {
                if (j == i || (is_boundary(st.a.velrho[i]) && is_boundary(st.a.velrho[j]))) continue;
                const int3v cc = g.decode(st.a.cell[j]);
                const real3 r = separation(st.a.pos[i], st.a.pos[j], cc.x - ci.x, cc.y - ci.y, cc.z - ci.z, g.cell_size);
                const real r2 = dot(r, r);
                if (r2 < p.support2 && r2 > real(1e-18) * p.support2) {
                    w.pairs.insert({st.a.id[i], st.a.id[j]});
                    ++w.visits;
                }
            }
        }
    }
    return w;
}

void expect_brute_force_set(const SortedState& st, real reach, const char* what) {
    const BuiltClusters b = build_clusters(st, reach);
    const PairSet expected = brute_force_pairs(st);
    const Walked w = walk_pairs(st, b);
    ASSERT_GT(expected.size(), 1000u) << what;
    EXPECT_EQ(w.visits, w.pairs.size()) << what << ": a pair visited twice";
    EXPECT_EQ(w.pairs.size(), expected.size()) << what;
    EXPECT_TRUE(w.pairs == expected) << what;
    std::size_t entries = 0;
    for (std::uint32_t c : b.count) entries += c;
    std::printf("%s: %u particles, %zu clusters, %.1f listed clusters a cluster (%.1f bytes a particle), %.1f boxes "
                "tested a cluster; walk: %.1f candidates and %.1f neighbours a particle (%.1f%% inside the support)\n",
                what, st.end, b.boxes.size(), double(entries) / double(b.boxes.size()),
                4.0 * double(entries) / double(st.end), double(b.tested) / double(b.boxes.size()),
                double(w.candidates) / st.end, double(w.neighbours) / st.end,
                100.0 * double(w.neighbours) / double(w.candidates));
}

// A random cloud (a third walls) that fills its domain, so that clusters sit in edge and corner
// cells, on cells of the reach and of half the reach.
TEST(ClusterLists, FindExactlyTheBruteForcePairsInARandomCloud) {
    for (int n : {1, 2}) {
        const Scene s = test::random_scene(2400, 800, 0.3, 0.02, 4242u + n);
        const double reach = 1.1 * double(s.params.support);
        const SortedState st = sort_scene(s, n, reach);
        expect_brute_force_set(st, real(reach), n == 1 ? "random cloud, cells of the reach" : "random cloud, half cells");
    }
}

// The scene of `steps` steps of a small dam break (the column collapsing), as a scene again.
Scene flowing_dambreak(const char* dp, int steps) {
    Scene s = test::small_dambreak(dp);
    SolverOptions o;
    o.search = SearchOptions{2, true};
    Simulation sim(s, o);
    for (int k = 0; k < steps; ++k) sim.step();
    const SnapshotData snap = sim.snapshot();
    Scene moved = s;
    for (std::size_t k = 0; k < snap.id.size(); ++k) {
        const std::uint32_t id = snap.id[k];
        moved.position[id] = {snap.position[3 * k], snap.position[3 * k + 1], snap.position[3 * k + 2]};
        moved.velocity[id] = {snap.velocity[3 * k], snap.velocity[3 * k + 1], snap.velocity[3 * k + 2]};
    }
    return moved;
}

TEST(ClusterLists, FindExactlyTheBruteForcePairsInAFlowingDamBreak) {
    const Scene s = flowing_dambreak("0.025", 600);
    const double reach = 1.1 * double(s.params.support);
    expect_brute_force_set(sort_scene(s, 2, reach), real(reach), "dam break after 600 steps, half cells");
    expect_brute_force_set(sort_scene(s, 1, reach), real(reach), "dam break after 600 steps, cells of the reach");
}

// list_build = clusters (change 15): each particle's Verlet list built from its cluster's list
// of clusters (at cluster_reach_for_lists) holds the entries the stencil's build holds, in the
// same order, so the listed loop sums the same pairs in the same order either way.
// The rebuild's inputs on the GPU tell walls apart by cell (fluid_begin: each cell holds its
// walls first, as the scenes number them), and a wall's list then holds fluid only; a wall-only
// cluster lists no wall-only cluster, so lists built from clusters need them.
template <bool CellOffsets>
void expect_stencil_lists(const SortedState& st, int n, bool merge, real reach, const char* what) {
    const BuiltClusters b = build_clusters(st, cluster_reach_for_lists(reach, st.grid.view));
    std::vector<std::uint32_t> fluid_begin(st.start.size());
    for (std::size_t c = 0; c + 1 < st.start.size(); ++c) {
        std::uint32_t k = st.start[c];
        while (k < st.start[c + 1] && is_boundary(st.a.velrho[k])) ++k;
        fluid_begin[c] = k;
        for (; k < st.start[c + 1]; ++k) ASSERT_FALSE(is_boundary(st.a.velrho[k])) << what << ": cell " << c << " holds a wall after fluid";
    }
    fluid_begin.back() = st.start.back();
    ForceInputs in = st.inputs();
    in.fluid_begin = fluid_begin.data();
    const std::uint32_t cap = 400, stride = st.end;
    std::vector<std::uint32_t> from_stencil(std::size_t(cap) * stride), from_clusters(std::size_t(cap) * stride);
    std::size_t entries = 0, lists_differ = 0;
    dispatch_search(SearchOptions{n, merge}, [&](auto srch) {
        using Search = typename decltype(srch)::type;
        if constexpr (Search::n <= ListEntry::reach_cells) for (std::uint32_t i = 0; i < st.end; ++i) {
            const std::uint32_t a =
                build_particle_list<Search, CellOffsets>(i, in, reach * reach, from_stencil.data(), stride, cap);
            const std::uint32_t c = build_particle_list_from_clusters<CellOffsets>(i, in, b.list(), reach * reach,
                                                                                   from_clusters.data(), stride, cap);
            ASSERT_LE(a, cap) << what;
            entries += a;
            bool same = a == c;
            for (std::uint32_t k = 0; same && k < a; ++k)
                same = from_stencil[std::size_t(k) * stride + i] == from_clusters[std::size_t(k) * stride + i];
            lists_differ += !same;
        }
    });
    std::printf("%s, n = %d, merge = %d, cell offsets %d: %zu entries, %zu of %u lists differ\n", what, n, int(merge),
                int(CellOffsets), entries, lists_differ, st.end);
    EXPECT_GT(entries, 20u * st.end) << what;
    EXPECT_EQ(lists_differ, 0u) << what;
}

TEST(ClusterLists, BuildTheStencilsPerParticleListsOnARandomCloudAndAFlowingDamBreak) {
    const Scene cloud = test::random_scene(2400, 800, 0.3, 0.02, 9090u);
    const Scene flowing = flowing_dambreak("0.025", 600);
    for (const Scene* s : {&cloud, &flowing}) {
        const char* what = s == &cloud ? "random cloud" : "dam break after 600 steps";
        const double reach = 1.1 * double(s->params.support);
        for (const SearchOptions o : {SearchOptions{1, false}, SearchOptions{2, true}, SearchOptions{2, false}}) {
            const SortedState st = sort_scene(*s, o.cells_per_support, reach);
            expect_stencil_lists<false>(st, o.cells_per_support, o.merge, real(reach), what);
            expect_stencil_lists<true>(st, o.cells_per_support, o.merge, real(reach), what);
        }
    }
}

// Every cluster with fluid lists itself, and a wall-only cluster lists no wall-only one.
TEST(ClusterLists, WallOnlyClustersListNoWallOnlyClusterAndEveryClusterListsItself) {
    const Scene s = test::random_scene(1600, 800, 0.3, 0.02, 77u);
    const double reach = 1.1 * double(s.params.support);
    const SortedState st = sort_scene(s, 2, reach);
    const BuiltClusters b = build_clusters(st, real(reach));
    std::size_t wall_only = 0;
    for (std::uint32_t c = 0; c < b.boxes.size(); ++c) {
        bool self = false;
        for (std::uint32_t k = 0; k < b.count[c]; ++k) {
            const std::uint32_t cj = b.index[std::size_t(k) * b.boxes.size() + c];
            self = self || cj == c;
            EXPECT_TRUE(b.boxes[c].has_fluid() || b.boxes[cj].has_fluid()) << "clusters " << c << " and " << cj;
        }
        wall_only += !b.boxes[c].has_fluid();
        EXPECT_TRUE(self || !b.boxes[c].has_fluid()) << "cluster " << c;
    }
    EXPECT_GT(wall_only, 0u);
}

// Not checks: the cluster lists of DualSPHysics' dam break (half cells, skin 0.1), for change
// 14's prediction: at its benchmark size (1.04M particles, dp 0.0045) at rest, a few seconds on
// two cores, and in flow at dp 0.02 (12K particles) after 0.3 s of the collapse (cell search on
// the host), about two minutes. Run them with --gtest_also_run_disabled_tests.
void print_dambreak_clusters(const Scene& s, const char* what) {
    const double reach = 1.1 * double(s.params.support);
    const SortedState st = sort_scene(s, 2, reach);
    const BuiltClusters b = build_clusters(st, real(reach), 1000);
    unsigned long long candidates = 0, neighbours = 0;
    const ForceInputs in = st.inputs();
    const ClusterList list = b.list();
#pragma omp parallel for reduction(+ : candidates, neighbours)
    for (std::int64_t i = 0; i < std::int64_t(st.end); ++i) {
        const SearchWork w = particle_cluster_work(std::uint32_t(i), in, list, st.params);
        candidates += w.candidates;
        neighbours += w.neighbours;
    }
    // The per-particle lists' entries (every candidate within the reach, walls' fluid only as
    // the GPU builds them) and the cell search's candidates on the same cells.
    unsigned long long entries_pp = 0, stencil = 0;
#pragma omp parallel for reduction(+ : entries_pp, stencil)
    for (std::int64_t i = 0; i < std::int64_t(st.end); ++i) {
        const int3v c = st.grid.view.decode(st.a.cell[std::size_t(i)]);
        const bool wall = is_boundary(st.a.velrho[std::size_t(i)]);
        CellSearch<2, true>::visit(st.grid.view, st.start.data(), st.a.cell.data(), c,
                                   [&](std::uint32_t j, int dx, int dy, int dz) {
                                       ++stencil;
                                       if (j == std::uint32_t(i) || (wall && is_boundary(st.a.velrho[j]))) return;
                                       const real3 r = separation(st.a.pos[std::size_t(i)], st.a.pos[j], dx, dy, dz,
                                                                  st.grid.view.cell_size);
                                       if (dot(r, r) < real(reach * reach)) ++entries_pp;
                                   });
    }
    std::size_t entries = 0, longest = 0;
    std::vector<std::uint32_t> sorted_counts = b.count;
    std::sort(sorted_counts.begin(), sorted_counts.end());
    for (std::uint32_t c : b.count) {
        entries += c;
        longest = std::max<std::size_t>(longest, c);
    }
    const double n = double(st.end), nc = double(b.clusters());
    const double capacity = double(longest + longest / 5 + 8);
    std::printf("%s: %u particles, %zu clusters (%.2f particles a cluster), %.1f listed clusters a cluster (median %u, "
                "99.9%% %u, longest %zu), %.1f boxes tested a cluster\n",
                what, st.end, b.boxes.size(), n / nc, double(entries) / nc, sorted_counts[sorted_counts.size() / 2],
                sorted_counts[sorted_counts.size() * 999 / 1000], longest, double(b.tested) / nc);
    std::printf("  walk: %.1f candidates and %.1f neighbours a particle (%.1f%% inside the support); per-particle "
                "lists: %.1f entries a particle; the n = 2 merged stencil: %.1f candidates a particle\n",
                double(candidates) / n, double(neighbours) / n, 100.0 * double(neighbours) / double(candidates),
                double(entries_pp) / n, double(stencil) / n);
    std::printf("  bytes a particle: entries %.1f (as CSR), column-major at the GPU's capacity %.1f, with boxes, "
                "counts, first particles and each particle's cluster %.1f, plus 8 of cell coordinates on the GPU\n",
                4.0 * double(entries) / n, 4.0 * capacity * nc / n,
                (4.0 * capacity * nc + 32.0 * nc + 8.0 * nc) / n + 4.0);
}

TEST(ClusterLists, DISABLED_DamBreak104MAtRest) {
    print_dambreak_clusters(make_scene("dsph-dambreak", {{"dp", "0.0045"}}), "dsph-dambreak dp 0.0045 at rest");
}

TEST(ClusterLists, DISABLED_DamBreakInFlow) {
    Scene s = make_scene("dsph-dambreak", {{"dp", "0.02"}});
    SolverOptions o;
    o.search = SearchOptions{2, true};
    Simulation sim(s, o);
    while (sim.time() < 0.3) sim.step();
    const SnapshotData snap = sim.snapshot();
    for (std::size_t k = 0; k < snap.id.size(); ++k) {
        const std::uint32_t id = snap.id[k];
        s.position[id] = {snap.position[3 * k], snap.position[3 * k + 1], snap.position[3 * k + 2]};
    }
    print_dambreak_clusters(s, "dsph-dambreak dp 0.02 at 0.3 s");
}

}  // namespace
}  // namespace sph
