// Every search strategy finds exactly the brute-force neighbour set, including particles at
// the edges of the domain, and the work counters agree with it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include "physics/dispatch.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

PairSet brute_force_pairs(const Scene& s) {
    PairSet pairs;
    const double r2max = double(s.params.support) * double(s.params.support);
    for (std::uint32_t i = 0; i < s.size(); ++i)
        for (std::uint32_t j = 0; j < s.size(); ++j) {
            if (i == j) continue;
            double r2 = 0;
            for (int k = 0; k < 3; ++k) r2 += (s.position[i][k] - s.position[j][k]) * (s.position[i][k] - s.position[j][k]);
            if (r2 < r2max) pairs.insert({i, j});
        }
    return pairs;
}

struct Strategy {
    int n;
    bool merge;
};

class NeighbourSearch : public ::testing::TestWithParam<Strategy> {};

TEST_P(NeighbourSearch, FindsExactlyTheBruteForceSet) {
    const Strategy st = GetParam();
    // Particles fill the whole domain, so many sit in edge and corner cells.
    Scene s = test::random_scene(1500, 0, 0.3, 0.02, 1234u + st.n * 2 + st.merge);
    const PairSet expected = brute_force_pairs(s);
    const SearchOptions opt{st.n, st.merge};
    const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, st.n);
    auto d = make_host_subdomain({s.params, g.view, s.kernel, true, opt}, s.size());
    d->upload(make_particle_arrays(s, g));
    d->sort_by_cell();
    const ParticleArrays a = d->download();
    ASSERT_TRUE(std::is_sorted(a.cell.begin(), a.cell.end()));

    std::vector<std::uint32_t> start(g.view.cell_count() + 1);
    for (std::uint32_t c = 0; c <= g.view.cell_count(); ++c)
        start[c] = std::uint32_t(std::lower_bound(a.cell.begin(), a.cell.end(), c) - a.cell.begin());

    PairSet found;
    dispatch_search(opt, [&](auto tag) {
        using Search = typename decltype(tag)::type;
        const real3 cs = g.view.cell_size;
        for (std::uint32_t i = 0; i < a.size(); ++i) {
            Search::visit(g.view, start.data(), a.cell.data(), g.view.decode(a.cell[i]),
                          [&](std::uint32_t j, int dx, int dy, int dz) {
                              const real3 r = separation(a.pos[i], a.pos[j], dx, dy, dz, cs);
                              const real r2 = dot(r, r);
                              if (r2 < s.params.support2 && r2 > real(1e-18) * s.params.support2)
                                  found.insert({a.id[i], a.id[j]});
                          });
        }
    });
    // Pairs at exactly the support radius may differ by float rounding; there are none at
    // random positions, so the sets must match exactly.
    EXPECT_EQ(found.size(), expected.size());
    EXPECT_TRUE(found == expected);
    const WorkCounters w = d->count_work();
    EXPECT_EQ(w.neighbours, expected.size());
    EXPECT_GE(w.candidates, w.neighbours);
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, NeighbourSearch,
                         ::testing::Values(Strategy{1, false}, Strategy{1, true}, Strategy{2, false}, Strategy{2, true},
                                           Strategy{3, false}, Strategy{3, true}, Strategy{4, false},
                                           Strategy{4, true}),
                         [](const auto& info) {
                             return "n" + std::to_string(info.param.n) + (info.param.merge ? "_merged" : "_cells");
                         });

// A boundary particle on the GPU walks only the fluid of each stencil cell
// (CellSearch::visit_fluid_cells, from each cell's first fluid particle): exactly visit()'s
// fluid candidates, in visit()'s order, with the same cell offsets. Half the particles are
// boundary, so cells mix both kinds; open and periodic grids, merged or not.
struct RangeCase {
    int n;
    bool merge, periodic;
};
class StencilFluidCells : public ::testing::TestWithParam<RangeCase> {};

std::string range_case_name(const ::testing::TestParamInfo<RangeCase>& info) {
    return "n" + std::to_string(info.param.n) + (info.param.merge ? "_merged" : "_cells") +
           (info.param.periodic ? "_periodic" : "_open");
}

// One visited candidate with its cell offset, comparable as a whole.
using Visit = std::vector<std::array<std::uint32_t, 4>>;
std::array<std::uint32_t, 4> entry(std::uint32_t j, int dx, int dy, int dz) {
    return {j, std::uint32_t(dx + 8), std::uint32_t(dy + 8), std::uint32_t(dz + 8)};
}

// A sorted random scene (half boundary particles) with its cell starts and each cell's first
// fluid particle, as the GPU's force loop reads them.
struct SortedCells {
    SearchOptions opt;  // the case's search: n and Cell Merging
    Grid grid;
    PhysicsParams params;
    ParticleArrays a;
    std::vector<std::uint32_t> start, fluid_begin;
};

// A random scene sorted for one RangeCase; each suite passes its own seed_base, and each case
// gets a seed of its own from it.
SortedCells sorted_cells(const RangeCase& rc, std::uint32_t seed_base) {
    const SearchOptions opt{rc.n, rc.merge};
    const std::uint32_t seed = seed_base + rc.n * 4 + rc.merge * 2 + rc.periodic;
    Scene s = test::random_scene(1200, 600, 0.3, 0.02, seed);
    const bool periodic[3] = {rc.periodic, rc.periodic, rc.periodic};
    SortedCells out{opt, make_grid(s.lo.data(), s.hi.data(), s.params.support, rc.n, periodic), s.params, {}, {}, {}};
    auto d = make_host_subdomain({s.params, out.grid.view, s.kernel, true, opt}, s.size());
    d->upload(make_particle_arrays(s, out.grid));
    d->sort_by_cell();
    out.a = d->download();
    const std::uint32_t ncells = out.grid.view.cell_count();
    out.start.resize(ncells + 1);
    out.fluid_begin.resize(ncells + 1);
    for (std::uint32_t c = 0; c <= ncells; ++c)
        out.start[c] = std::uint32_t(std::lower_bound(out.a.cell.begin(), out.a.cell.end(), c) - out.a.cell.begin());
    // The reference fluid_begin: a scan of each cell, not the GPU's predecessor rule.
    for (std::uint32_t c = 0; c < ncells; ++c) {
        std::uint32_t k = out.start[c];
        while (k < out.start[c + 1] && is_boundary(out.a.velrho[k])) ++k;
        out.fluid_begin[c] = k;
    }
    out.fluid_begin[ncells] = out.start[ncells];
    return out;
}

// The GPU's listed loop (ListedLoopPolicySm90's choices: cells read as coordinates, the
// density loaded before the support test, or j's position and velocity-density loaded whole
// and kept, the list read one or two entries ahead, walls' lists of fluid only) must give the
// host's listed loop's sums bit for bit: the same pairs in the same order through the same
// arithmetic. Both run here, on the host.
template <int Lookahead, bool WholeLoads = false, bool ChunkLoads = false>
struct GpuLikeListedLoop {
    static constexpr bool packed_cells = true;
    static constexpr bool early_loads = true;
    static constexpr bool whole_loads = WholeLoads;
    static constexpr int index_lookahead = Lookahead;
    static constexpr bool chunk_loads = ChunkLoads;
    static constexpr bool entry_offsets = false;
};

// The lists a rebuild gives every particle inside the domain, as the GPU builds them (walls'
// lists of fluid only where in.fluid_begin is set), with plain or ListEntry entries.
template <bool CellOffsets = false>
void build_all_lists(const SortedCells& sc, const ForceInputs& in, real reach, std::uint32_t capacity,
                     std::vector<std::uint32_t>& index, std::vector<std::uint32_t>& count) {
    const std::uint32_t n = std::uint32_t(sc.a.size());
    const GridView& g = sc.grid.view;
    index.assign(std::size_t(capacity) * n, 0);
    count.assign(n, 0);
    dispatch_search(sc.opt, [&](auto tag) {
        using Search = typename decltype(tag)::type;
        if constexpr (!CellOffsets || Search::n <= ListEntry::reach_cells) {
            for (std::uint32_t i = 0; i < n; ++i)
                if (sc.a.cell[i] < g.out_of_domain())
                    count[i] = build_particle_list<Search, CellOffsets>(i, in, reach * reach, index.data(), n, capacity);
        } else {
            FAIL() << "a stencil too wide for cell offsets";
        }
    });
}

class ListedLoopChoices : public ::testing::TestWithParam<RangeCase> {};

TEST_P(ListedLoopChoices, GiveTheHostLoopsSumsBitwise) {
    const RangeCase rc = GetParam();
    SortedCells sc = sorted_cells(rc, 9090u);
    // Each particle's P / rho^2 in its position's w, as the integration leaves it, so that the
    // pressure term is in the sums compared.
    for (std::size_t k = 0; k < sc.a.size(); ++k) sc.a.pos[k].w = pressure_over_rho2(sc.params, density(sc.a.velrho[k]));
    const GridView& g = sc.grid.view;
    const ParticleArrays& a = sc.a;
    const PhysicsParams& p = sc.params;
    const std::uint32_t n = std::uint32_t(a.size());
    std::vector<CellCoords> coords(n);
    for (std::uint32_t i = 0; i < n; ++i) coords[i] = pack_cell_coords(g.decode(a.cell[i]), a.cell[i] < g.out_of_domain());
    const ForceInputs host_in{a.pos.data(), a.velrho.data(), a.velrho_prev.data(), a.cell.data(), sc.start.data(),
                              nullptr, g, nullptr};
    ForceInputs gpu_in = host_in;
    gpu_in.fluid_begin = sc.fluid_begin.data();
    gpu_in.cell_coords = coords.data();
    const real reach = real(1.1) * p.support;
    const std::uint32_t capacity = 400;
    std::vector<std::uint32_t> host_index, host_count, gpu_index, gpu_count, coded_index, coded_count;
    build_all_lists(sc, host_in, reach, capacity, host_index, host_count);
    build_all_lists(sc, gpu_in, reach, capacity, gpu_index, gpu_count);
    const NeighbourList host_list{host_index.data(), host_count.data(), n}, gpu_list{gpu_index.data(), gpu_count.data(), n};
    // Entries with cell offsets (open grids): at a rebuild the frame is the positions themselves.
    ForceInputs framed_in = gpu_in;
    framed_in.build_frame = a.pos.data();
    if (!rc.periodic) build_all_lists<true>(sc, gpu_in, reach, capacity, coded_index, coded_count);
    const NeighbourList coded_list{coded_index.data(), coded_count.data(), n, true};
    const CubicSpline kernel(p.h);
    std::size_t walls_shorter = 0, compared = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (a.cell[i] >= g.out_of_domain()) continue;
        ASSERT_LE(host_count[i], capacity);
        if (gpu_count[i] < host_count[i]) ++walls_shorter;
        const real4 want = particle_force_listed<CubicSpline, true>(i, host_in, host_list, p, kernel);
        const real4 one = particle_force_listed<CubicSpline, true, GpuLikeListedLoop<1>>(i, gpu_in, gpu_list, p, kernel);
        const real4 two = particle_force_listed<CubicSpline, true, GpuLikeListedLoop<2>>(i, gpu_in, gpu_list, p, kernel);
        const real4 whole =
            particle_force_listed<CubicSpline, true, GpuLikeListedLoop<2, true>>(i, gpu_in, gpu_list, p, kernel);
        ASSERT_EQ(std::memcmp(&want, &one, sizeof want), 0) << "particle " << i << ", lookahead 1";
        ASSERT_EQ(std::memcmp(&want, &two, sizeof want), 0) << "particle " << i << ", lookahead 2";
        ASSERT_EQ(std::memcmp(&want, &whole, sizeof want), 0) << "particle " << i << ", whole loads";
        const real4 chunked =
            particle_force_listed<CubicSpline, true, GpuLikeListedLoop<0, true, true>>(i, gpu_in, gpu_list, p, kernel);
        ASSERT_EQ(std::memcmp(&want, &chunked, sizeof want), 0) << "particle " << i << ", chunk loads";
        if (!rc.periodic) {
            ASSERT_EQ(coded_count[i], gpu_count[i]);
            const real4 coded = particle_force_listed<CubicSpline, true, WithEntryOffsets<GpuLikeListedLoop<2, true>>>(
                i, framed_in, coded_list, p, kernel);
            ASSERT_EQ(std::memcmp(&want, &coded, sizeof want), 0) << "particle " << i << ", entries with cell offsets";
            const real4 coded_chunks =
                particle_force_listed<CubicSpline, true, WithEntryOffsets<GpuLikeListedLoop<0, true, true>>>(
                    i, framed_in, coded_list, p, kernel);
            ASSERT_EQ(std::memcmp(&want, &coded_chunks, sizeof want), 0)
                << "particle " << i << ", entries with cell offsets, chunk loads";
        }
        ++compared;
    }
    EXPECT_GT(compared, n / 2);
    EXPECT_GT(walls_shorter, 0u);  // walls' lists left their walls out
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, ListedLoopChoices,
                         ::testing::Values(RangeCase{1, false, false}, RangeCase{2, true, false},
                                           RangeCase{3, true, false}, RangeCase{1, false, true},
                                           RangeCase{2, true, true}),
                         range_case_name);

// Between rebuilds the GPU keeps, for lists with cell offsets, each particle's position against
// its cell of the rebuild (particle_advance with a build frame), where the plain entries read
// the cells that advance keeps up. After a move of up to ~0.5 cells, which takes many
// particles into other cells and some out of the domain, both loops must give the same sums:
// to the bit for a particle whose pairs all stayed in their cells (the frame is then the
// position itself), within rounding for the rest. Wrong cell offsets would be off by a cell.
class ListedLoopBuildFrame : public ::testing::TestWithParam<RangeCase> {};

TEST_P(ListedLoopBuildFrame, FollowsParticlesIntoOtherCells) {
    const RangeCase rc = GetParam();
    const SortedCells sc = sorted_cells(rc, 5151u);
    const GridView& g = sc.grid.view;
    const PhysicsParams& p = sc.params;
    const std::uint32_t n = std::uint32_t(sc.a.size());
    const real reach = real(1.1) * p.support;
    const std::uint32_t capacity = 400;
    std::vector<CellCoords> coords(n);
    for (std::uint32_t i = 0; i < n; ++i) coords[i] = pack_cell_coords(g.decode(sc.a.cell[i]), sc.a.cell[i] < g.out_of_domain());
    const ForceInputs rebuilt{sc.a.pos.data(), sc.a.velrho.data(), sc.a.velrho_prev.data(), sc.a.cell.data(),
                              sc.start.data(), sc.fluid_begin.data(), g, coords.data()};
    std::vector<std::uint32_t> plain_index, plain_count, coded_index, coded_count;
    build_all_lists(sc, rebuilt, reach, capacity, plain_index, plain_count);
    build_all_lists<true>(sc, rebuilt, reach, capacity, coded_index, coded_count);

    // The same move twice: cells kept up (plain entries) and cells frozen with a frame.
    ParticleArrays kept = sc.a, framed = sc.a;
    std::vector<CellCoords> kept_coords = coords, frozen_coords = coords;
    std::vector<real4> frame(sc.a.pos);
    std::mt19937 rng(99u);
    std::uniform_real_distribution<float> u(-1, 1);
    // Only the fluid of the grid's upper half in x moves: the lower half keeps particles whose
    // pairs all stay in their cells.
    for (std::uint32_t i = 0; i < n; ++i)
        if (!is_boundary(sc.a.velrho[i]) && sc.a.cell[i] < g.out_of_domain() && 2 * g.decode(sc.a.cell[i]).x >= g.nx) {
            const real4 v{u(rng), u(rng), u(rng), density(sc.a.velrho[i])};
            kept.velrho[i] = framed.velrho[i] = v;
        }
    const std::vector<real4> force(n, real4{0, 0, 0, 0});
    const TimeStep step = euler_step(real(0.3) * g.cell_size.x);
    for (std::uint32_t i = 0; i < n; ++i) {
        particle_advance(i, kept.pos.data(), kept.velrho.data(), kept.velrho_prev.data(), kept.cell.data(),
                         KeptCells{kept_coords.data(), nullptr}, force.data(), nullptr, step, g, p);
        particle_advance(i, framed.pos.data(), framed.velrho.data(), framed.velrho_prev.data(), framed.cell.data(),
                         KeptCells{frozen_coords.data(), frame.data()}, force.data(), nullptr, step, g, p);
    }
    ASSERT_EQ(std::memcmp(kept.pos.data(), framed.pos.data(), n * sizeof(real4)), 0);
    ASSERT_EQ(kept.cell, framed.cell);
    std::vector<bool> moved(n);
    std::size_t changed_cells = 0, left = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        moved[i] = kept.cell[i] != sc.a.cell[i];
        changed_cells += moved[i];
        left += kept.cell[i] >= g.out_of_domain() && sc.a.cell[i] < g.out_of_domain();
    }
    EXPECT_GT(changed_cells, n / 20);
    EXPECT_GT(left, 0u);

    const ForceInputs plain_in{kept.pos.data(), kept.velrho.data(), kept.velrho_prev.data(), kept.cell.data(),
                               sc.start.data(), sc.fluid_begin.data(), g, kept_coords.data()};
    ForceInputs framed_in{framed.pos.data(), framed.velrho.data(), framed.velrho_prev.data(), framed.cell.data(),
                          sc.start.data(), sc.fluid_begin.data(), g, frozen_coords.data()};
    framed_in.build_frame = frame.data();
    const NeighbourList plain_list{plain_index.data(), plain_count.data(), n};
    const NeighbourList coded_list{coded_index.data(), coded_count.data(), n, true};
    const CubicSpline kernel(p.h);
    std::vector<real4> want(n), got(n);
    std::vector<bool> untouched(n, false);
    double scale = 0, drho_scale = 0;  // the largest |acceleration| and |d rho / dt|: the sums cancel
    std::size_t compared = 0, bitwise = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        if (sc.a.cell[i] >= g.out_of_domain() || kept.cell[i] >= g.out_of_domain()) continue;
        want[i] = particle_force_listed<CubicSpline, true, GpuLikeListedLoop<2, true>>(i, plain_in, plain_list, p, kernel);
        got[i] = particle_force_listed<CubicSpline, true, WithEntryOffsets<GpuLikeListedLoop<2, true>>>(
            i, framed_in, coded_list, p, kernel);
        bool still = !moved[i];
        for (std::uint32_t k = 0; k < plain_count[i]; ++k) still = still && !moved[plain_index[list_slot(k, i, n)]];
        untouched[i] = still;
        scale = std::max(scale, std::sqrt(double(dot(xyz(want[i]), xyz(want[i])))));
        drho_scale = std::max(drho_scale, std::abs(double(want[i].w)));
        ++compared;
    }
    ASSERT_GT(scale, 0.0);
    ASSERT_GT(drho_scale, 0.0);
    for (std::uint32_t i = 0; i < n; ++i) {
        if (sc.a.cell[i] >= g.out_of_domain() || kept.cell[i] >= g.out_of_domain()) continue;
        if (untouched[i]) {
            ASSERT_EQ(std::memcmp(&want[i], &got[i], sizeof(real4)), 0) << "particle " << i << ", nothing changed cells";
            ++bitwise;
        }
        const real3 d = xyz(want[i]) - xyz(got[i]);
        EXPECT_LE(std::sqrt(double(dot(d, d))), 1e-6 * scale) << "particle " << i;
        EXPECT_LE(std::abs(double(want[i].w) - double(got[i].w)), 1e-6 * drho_scale) << "particle " << i << ", d rho / dt";
    }
    EXPECT_GT(compared, n / 2);
    EXPECT_GT(bitwise, 0u);
    EXPECT_LT(bitwise, compared);
}

INSTANTIATE_TEST_SUITE_P(OpenGrids, ListedLoopBuildFrame,
                         ::testing::Values(RangeCase{1, false, false}, RangeCase{1, true, false},
                                           RangeCase{2, false, false}, RangeCase{2, true, false},
                                           RangeCase{3, true, false}),
                         range_case_name);

TEST_P(StencilFluidCells, GiveBoundaryParticlesExactlyVisitsFluidCandidates) {
    const RangeCase rc = GetParam();
    const SortedCells sc = sorted_cells(rc, 777u);
    const SearchOptions& opt = sc.opt;
    const Grid& g = sc.grid;
    const ParticleArrays& a = sc.a;
    const std::vector<std::uint32_t>& start = sc.start;
    const std::vector<std::uint32_t>& fluid_begin = sc.fluid_begin;
    for (std::uint32_t c = 0; c < g.view.cell_count(); ++c)
        for (std::uint32_t m = fluid_begin[c]; m < start[c + 1]; ++m) ASSERT_FALSE(is_boundary(a.velrho[m])) << "cell " << c;

    std::size_t boundary_particles = 0, skipped = 0;
    dispatch_search(opt, [&](auto tag) {
        using Search = typename decltype(tag)::type;
        for (std::uint32_t i = 0; i < a.size(); ++i) {
            if (!is_boundary(a.velrho[i])) continue;
            const int3v c = g.view.decode(a.cell[i]);
            Visit expected, got;
            Search::visit(g.view, start.data(), a.cell.data(), c, [&](std::uint32_t j, int dx, int dy, int dz) {
                if (is_boundary(a.velrho[j])) {
                    ++skipped;
                    return;
                }
                expected.push_back(entry(j, dx, dy, dz));
            });
            Search::visit_fluid_cells(g.view, start.data(), fluid_begin.data(), c,
                                      [&](std::uint32_t begin, std::uint32_t end, int dx, int dy, int dz) {
                                          for (std::uint32_t j = begin; j < end; ++j) got.push_back(entry(j, dx, dy, dz));
                                      });
            ASSERT_EQ(got, expected) << "boundary particle " << i;
            ++boundary_particles;
        }
    });
    EXPECT_GT(boundary_particles, 0u);
    EXPECT_GT(skipped, 0u);  // boundary particles did have boundary candidates to skip
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, StencilFluidCells,
                         ::testing::Values(RangeCase{1, false, false}, RangeCase{1, true, false},
                                           RangeCase{2, false, false}, RangeCase{2, true, false},
                                           RangeCase{4, true, false}, RangeCase{1, false, true},
                                           RangeCase{1, true, true}, RangeCase{2, true, true}),
                         range_case_name);

// The GPU's force loop takes each stencil range through add_range_by_hit_masks (test 32
// candidates, then run the pair body over the hits): it must hand the pair sums exactly the
// neighbours that visit() finds inside the support, in visit()'s order, with the same
// separations up to rounding; boundary particles their fluid neighbours only. Ranges longer
// than 32 candidates (merged runs) cross chunk boundaries.
class HitMaskTraversal : public ::testing::TestWithParam<RangeCase> {};

struct RecordedPairs {
    std::vector<std::uint32_t> j;
    std::vector<real3> rij;
    void add_neighbour(std::uint32_t jj, const real3& r, real) {
        j.push_back(jj);
        rij.push_back(r);
    }
};

TEST_P(HitMaskTraversal, HandsThePairSumsVisitsNeighboursInOrder) {
    const RangeCase rc = GetParam();
    const SortedCells sc = sorted_cells(rc, 4242u);
    const SearchOptions& opt = sc.opt;
    const GridView& g = sc.grid.view;
    const ParticleArrays& a = sc.a;
    const PhysicsParams& p = sc.params;
    const real support = p.support;
    const ForceInputs in{a.pos.data(), a.velrho.data(), a.velrho_prev.data(), a.cell.data(), sc.start.data(),
                         sc.fluid_begin.data(), g, nullptr};
    std::size_t pairs = 0, long_ranges = 0;
    dispatch_search(opt, [&](auto tag) {
        using Search = typename decltype(tag)::type;
        for (std::uint32_t i = 0; i < a.size(); ++i) {
            if (a.cell[i] >= g.out_of_domain()) continue;
            const bool fluid_i = !is_boundary(a.velrho[i]);
            const int3v c = g.decode(a.cell[i]);
            RecordedPairs expected, got;
            Search::visit(g, in.cell_start, in.cell, c, [&](std::uint32_t j, int dx, int dy, int dz) {
                const real3 r = separation(a.pos[i], a.pos[j], dx, dy, dz, g.cell_size);
                const real r2 = dot(r, r);
                if (r2 >= p.support2 || r2 <= real(1e-18) * p.support2) return;
                if (!fluid_i && is_boundary(a.velrho[j])) return;
                expected.add_neighbour(j, r, r2);
            });
            if (fluid_i) {
                Search::visit_ranges(g, in.cell_start, c,
                                     [&](std::uint32_t b, std::uint32_t e, int dx, int dy, typename Search::RangeZ z) {
                                         if (e - b > 32) ++long_ranges;
                                         add_range_by_hit_masks(got, a.pos[i], in, p, b, e, dx, dy,
                                                                [&](std::uint32_t j) { return z.of(in.cell, j); });
                                     });
            } else {
                Search::visit_fluid_cells(g, in.cell_start, in.fluid_begin, c,
                                          [&](std::uint32_t b, std::uint32_t e, int dx, int dy, int dz) {
                                              add_range_by_hit_masks(got, a.pos[i], in, p, b, e, dx, dy,
                                                                     [dz](std::uint32_t) { return dz; });
                                          });
            }
            ASSERT_EQ(got.j, expected.j) << "particle " << i;
            for (std::size_t k = 0; k < got.j.size(); ++k) {
                EXPECT_NEAR(got.rij[k].x, expected.rij[k].x, 1e-6 * support) << "particle " << i;
                EXPECT_NEAR(got.rij[k].y, expected.rij[k].y, 1e-6 * support) << "particle " << i;
                EXPECT_NEAR(got.rij[k].z, expected.rij[k].z, 1e-6 * support) << "particle " << i;
            }
            pairs += got.j.size();
        }
    });
    EXPECT_GT(pairs, a.size());  // several neighbours a particle: the test saw real work
    if (rc.merge && rc.n == 1) {  // runs of 3 cells of ~15 particles; smaller cells hold ~2
        EXPECT_GT(long_ranges, 0u);
    }
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, HitMaskTraversal,
                         ::testing::Values(RangeCase{1, false, false}, RangeCase{1, true, false},
                                           RangeCase{2, true, false}, RangeCase{4, true, false},
                                           RangeCase{1, false, true}, RangeCase{1, true, true},
                                           RangeCase{2, false, true}),
                         range_case_name);

// The GPU's compacted force loop walks every lane's stencil in step
// (CellSearch::visit_ranges_in_step): the same number of ranges around every cell, empty
// outside the grid, and, with a merged run's walls dropped for wall particles, exactly the
// candidates of visit() (walls: of visit_fluid_cells) in their order with their cell offsets.
// Cells at every edge of the grid, open and periodic (not merged across a periodic z face).
class StepwiseRanges : public ::testing::TestWithParam<RangeCase> {};

TEST_P(StepwiseRanges, GiveEachParticleItsCandidatesInVisitOrder) {
    const RangeCase rc = GetParam();
    const SortedCells sc = sorted_cells(rc, 9191u);
    const SearchOptions& opt = sc.opt;
    const GridView& g = sc.grid.view;
    const ParticleArrays& a = sc.a;
    std::size_t candidates = 0, dropped_walls = 0, empty_ranges = 0;
    dispatch_search(opt, [&](auto tag) {
        using Search = typename decltype(tag)::type;
        const unsigned side = 2 * Search::n + 1, steps = Search::merge ? side * side : side * side * side;
        for (std::uint32_t i = 0; i < a.size(); ++i) {
            if (a.cell[i] >= g.out_of_domain()) continue;
            const bool wall = is_boundary(a.velrho[i]);
            const int3v c = g.decode(a.cell[i]);
            Visit expected, got;
            Search::visit(g, sc.start.data(), a.cell.data(), c, [&](std::uint32_t j, int dx, int dy, int dz) {
                if (!wall || !is_boundary(a.velrho[j])) expected.push_back(entry(j, dx, dy, dz));
            });
            unsigned calls = 0;
            Search::visit_ranges_in_step(g, sc.start.data(), sc.fluid_begin.data(), c, true, wall,
                                         [&](std::uint32_t b, std::uint32_t e, int dx, int dy,
                                             typename Search::RangeZ z) {
                                             ++calls;
                                             if (b == e) ++empty_ranges;
                                             for (std::uint32_t j = b; j < e; ++j) {
                                                 if (wall && is_boundary(a.velrho[j])) {
                                                     ++dropped_walls;
                                                     continue;
                                                 }
                                                 got.push_back(entry(j, dx, dy, z.of(a.cell.data(), j)));
                                             }
                                         });
            ASSERT_EQ(calls, steps) << "particle " << i;
            ASSERT_EQ(got, expected) << "particle " << i;
            candidates += got.size();
            unsigned nonempty = 0;
            Search::visit_ranges_in_step(g, sc.start.data(), sc.fluid_begin.data(), c, false, wall,
                                         [&](std::uint32_t b, std::uint32_t e, int, int, typename Search::RangeZ) {
                                             nonempty += b != e;
                                         });
            ASSERT_EQ(nonempty, 0u) << "a lane that does not walk got a range, particle " << i;
        }
    });
    EXPECT_GT(candidates, 10 * a.size());
    if (!rc.periodic) {
        EXPECT_GT(empty_ranges, 0u);  // cells at the edges
    }
    if (rc.merge) {
        EXPECT_GT(dropped_walls, 0u);  // merged runs of wall particles held walls
    }
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, StepwiseRanges,
                         ::testing::Values(RangeCase{1, false, false}, RangeCase{1, true, false},
                                           RangeCase{2, false, false}, RangeCase{2, true, false},
                                           RangeCase{3, true, false}, RangeCase{1, false, true},
                                           RangeCase{2, false, true}),
                         range_case_name);

TEST(NeighbourSearch, CellMergingVisitsNineRangesInsteadOf27Cells) {
    Scene s = test::random_scene(400, 0, 0.3, 0.02, 99u, 0.5);  // margin: no particle at an edge
    for (bool merge : {false, true}) {
        const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, 1);
        auto d = make_host_subdomain({s.params, g.view, s.kernel, true, {1, merge}}, s.size());
        d->upload(make_particle_arrays(s, g));
        d->sort_by_cell();
        EXPECT_EQ(d->count_work().ranges, (merge ? 9u : 27u) * s.size());
    }
}
}  // namespace
}  // namespace sph

namespace sph {
namespace {

// A run of N steps with any strategy gives the same particles as traditional CLL: the same
// neighbour set, visited in another order, so only float rounding differs.
TEST(SearchStrategies, RunsAgreeWithTraditionalCll) {
    const Scene s = test::small_dambreak("0.04");
    auto run = [&](SearchOptions search) {
        SolverOptions o;
        o.search = search;
        o.fixed_dt = 2.5e-4;
        Simulation sim(s, o);
        for (int k = 0; k < 60; ++k) sim.step();
        return test::positions_by_id(sim.snapshot());
    };
    const auto reference = run(SearchOptions{});
    std::vector<SearchOptions> strategies;
    for (int n = 1; n <= 4; ++n)
        for (bool merge : {false, true}) strategies.push_back({n, merge});
    SearchOptions verlet;
    verlet.verlet = true;
    strategies.push_back(verlet);
    verlet.rebuild_every = 10;
    strategies.push_back(verlet);
    for (const SearchOptions& st : strategies) {
        const auto p = run(st);
        double worst = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
            for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(p[i][k] - reference[i][k]));
        EXPECT_LT(worst, 1e-4 * s.dp) << "n = " << st.cells_per_support << ", merge = " << st.merge
                                      << ", verlet = " << st.verlet << ", rebuild every " << st.rebuild_every;
    }
}

TEST(SearchStrategies, VerletListsRebuildOnDisplacementAndHoldEveryNeighbour) {
    const Scene s = test::small_dambreak("0.04");
    SolverOptions o;
    o.search.verlet = true;
    Simulation sim(s, o);
    for (int k = 0; k < 200; ++k) sim.step();
    // The column has started to fall: lists were rebuilt, but far fewer times than steps.
    EXPECT_GT(sim.neighbour_list_builds(), 1);
    EXPECT_LT(sim.neighbour_list_builds(), 100);
    EXPECT_GT(sim.neighbour_list_bytes(), 50 * sizeof(std::uint32_t) * s.size());
}

// What makes reusing the lists exact: while every particle is within half the skin of where
// the lists were built, every pair now inside the support was within support + skin then. The
// step that reuses them takes its forces where the last step left the particles; so at every
// step that does not rebuild, no particle may be farther than half the skin from its place at
// the last build. The solver knows no particle's displacement: it sums a bound from the step
// statistics (Simulation::verlet_list_expired), which this holds to the particles' own paths.
TEST(SearchStrategies, VerletListsAreReusedOnlyWhileEveryParticleIsWithinHalfTheSkin) {
    const Scene s = test::small_dambreak("0.04");
    SolverOptions o;
    o.search.verlet = true;
    o.search.cells_per_support = 2;
    Simulation sim(s, o);
    const double half_skin = 0.5 * o.search.skin * double(s.params.support);
    auto farthest = [](const std::vector<std::array<double, 3>>& a, const std::vector<std::array<double, 3>>& b) {
        double d2 = 0;
        for (std::size_t i = 0; i < a.size(); ++i) {
            const double dx = a[i][0] - b[i][0], dy = a[i][1] - b[i][1], dz = a[i][2] - b[i][2];
            d2 = std::max(d2, dx * dx + dy * dy + dz * dz);
        }
        return std::sqrt(d2);
    };
    auto before = test::positions_by_id(sim.snapshot()), built = before;
    long builds = sim.neighbour_list_builds(), reused = 0;
    double worst = 0;
    for (int k = 0; k < 600; ++k) {
        sim.step();
        if (sim.neighbour_list_builds() != builds) {
            builds = sim.neighbour_list_builds();
            built = before;  // this step sorted and built on the state the last one left
        } else {
            ++reused;
            worst = std::max(worst, farthest(before, built) / half_skin);
        }
        before = test::positions_by_id(sim.snapshot());
    }
    std::printf("%ld of 600 steps reused the lists; the farthest a particle had moved then: %.4f of half the skin "
                "(%ld builds)\n", reused, worst, builds);
    EXPECT_GT(builds, 10) << "the flow should have rebuilt the lists many times";
    EXPECT_GT(worst, 0.5) << "the lists should have been reused close to their limit";
    EXPECT_LE(worst, 1.0);
}

// Between rebuilds two particles may close the skin. A list built on cells of the support
// radius would miss pairs just beyond it in cells the stencil does not reach (it did, before
// the check: one particle's forces in this cloud came out wrong); on cells of support + skin
// (what the Simulation makes for Verlet lists) it holds them all. Each particle
// moves 0.45 skin after the build, then the listed forces must equal a fresh cell search's.
TEST(SearchStrategies, VerletListsHoldPairsThatCloseTheSkin) {
    Scene s = test::random_scene(2500, 0, 0.3, 0.02, 11u, 0.05);
    const double skin = 0.1 * double(s.params.support);
    std::mt19937 rng(12u);
    std::normal_distribution<double> nd(0, 1);
    const double dt = 1e-3, speed = 0.45 * skin / dt;
    for (auto& v : s.velocity) {
        double d[3] = {nd(rng), nd(rng), nd(rng)};
        const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        v = {float(speed * d[0] / norm), float(speed * d[1] / norm), float(speed * d[2] / norm)};
    }
    auto forces_by_id = [](const ParticleArrays& a) {
        std::vector<real4> f(a.size());
        for (std::size_t k = 0; k < a.size(); ++k) f[a.id[k]] = a.force[k];
        return f;
    };
    auto listed_after_move = [&](double cell_reach) {
        const Grid g = make_grid(s.lo.data(), s.hi.data(), cell_reach, 1);
        auto d = make_host_subdomain({s.params, g.view, s.kernel, true, {1, false}}, s.size());
        d->upload(make_particle_arrays(s, g));
        d->sort_by_cell();
        d->advance(euler_step(0));
        d->build_neighbour_list(real(skin));
        d->advance(euler_step(real(dt)));  // forces are still zero: a straight move
        d->compute_forces_listed();
        ParticleArrays moved = d->download();
        // The reference: a cell search of the moved state, sorted afresh.
        auto fresh = make_host_subdomain({s.params, g.view, s.kernel, true, {1, false}}, s.size());
        fresh->upload(moved);
        fresh->sort_by_cell();
        fresh->compute_forces();
        return std::make_pair(forces_by_id(moved), forces_by_id(fresh->download()));
    };
    auto mismatches = [](const std::pair<std::vector<real4>, std::vector<real4>>& f) {
        int bad = 0;
        for (std::size_t i = 0; i < f.first.size(); ++i) {
            const real4 a = f.first[i], b = f.second[i];
            const double diff = std::abs(a.x - b.x) + std::abs(a.y - b.y) + std::abs(a.z - b.z) + std::abs(a.w - b.w);
            const double size = std::abs(b.x) + std::abs(b.y) + std::abs(b.z) + std::abs(b.w);
            if (diff > 1e-4 * size + 1e-6) ++bad;
        }
        return bad;
    };
    EXPECT_EQ(mismatches(listed_after_move(double(s.params.support) + skin)), 0);
    // A support-sized stencil loses pairs, which the subdomain refuses to risk.
    EXPECT_THROW(listed_after_move(double(s.params.support)), RunError);
}

}  // namespace
}  // namespace sph
