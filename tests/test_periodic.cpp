// Periodic boundaries: every search strategy finds the brute-force periodic neighbour set
// (all images within the support, computed in double), particles that cross a periodic face
// keep their neighbours, a lattice at rest stays at rest, and the options periodic axes
// cannot run with are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

#include "core/error.hpp"
#include "physics/dispatch.hpp"
#include "test_support.hpp"

namespace sph {
namespace {

// (i, j, image): j's image shifted by image * period along each axis lies within the support.
using ImagePair = std::tuple<std::uint32_t, std::uint32_t, int, int, int>;
using ImagePairs = std::set<ImagePair>;

ImagePairs brute_force_images(const Scene& s) {
    ImagePairs pairs;
    const double r2max = double(s.params.support) * double(s.params.support);
    double period[3], shortest = 1e30;
    for (int a = 0; a < 3; ++a) {
        period[a] = s.hi[a] - s.lo[a];
        shortest = std::min(shortest, period[a]);
    }
    const int reach = int(std::ceil(double(s.params.support) / shortest));  // periods an image can be away
    for (std::uint32_t i = 0; i < s.size(); ++i)
        for (std::uint32_t j = 0; j < s.size(); ++j)
            for (int kx = -reach; kx <= reach; ++kx)
                for (int ky = -reach; ky <= reach; ++ky)
                    for (int kz = -reach; kz <= reach; ++kz) {
                        if (i == j && kx == 0 && ky == 0 && kz == 0) continue;
                        const int k[3] = {kx, ky, kz};
                        double r2 = 0;
                        for (int a = 0; a < 3; ++a) {
                            const double r = s.position[i][a] - (s.position[j][a] + k[a] * period[a]);
                            r2 += r * r;
                        }
                        if (r2 < r2max) pairs.insert({i, j, kx, ky, kz});
                    }
    return pairs;
}

// A random periodic box: side x side x depth, periodic on every axis.
Scene periodic_box(double side, double depth, unsigned seed, std::size_t n) {
    Scene s = test::random_scene(n, 0, side, 0.02, seed);
    for (auto& p : s.position) p[2] *= depth / side;
    s.hi[2] = depth;
    s.periodic = {true, true, true};
    return s;
}

// What a cell search visits from the subdomain's sorted state, as (i, j, image) by id: the
// image is read back from the separation the search produced against the absolute positions.
ImagePairs searched_images(const Scene& s, const Grid& g, const SearchOptions& opt, Subdomain& d) {
    const ParticleArrays a = d.download();
    std::vector<std::uint32_t> start(g.view.cell_count() + 1);
    for (std::uint32_t c = 0; c <= g.view.cell_count(); ++c)
        start[c] = std::uint32_t(std::lower_bound(a.cell.begin(), a.cell.end(), c) - a.cell.begin());
    ImagePairs found;
    dispatch_search(opt, [&](auto tag) {
        using Search = typename decltype(tag)::type;
        for (std::uint32_t i = 0; i < a.size(); ++i)
            Search::visit(g.view, start.data(), a.cell.data(), g.view.decode(a.cell[i]),
                          [&](std::uint32_t j, int dx, int dy, int dz) {
                              const real3 r = separation(a.pos[i], a.pos[j], dx, dy, dz, g.view.cell_size);
                              const real r2 = dot(r, r);
                              if (!(r2 < s.params.support2 && r2 > real(1e-18) * s.params.support2)) return;
                              const double rr[3] = {r.x, r.y, r.z};
                              int k[3];
                              for (int ax = 0; ax < 3; ++ax) {
                                  const double direct = s.position[a.id[i]][ax] - s.position[a.id[j]][ax];
                                  k[ax] = int(std::lround((direct - rr[ax]) / (s.hi[ax] - s.lo[ax])));
                              }
                              const bool fresh = found.insert({a.id[i], a.id[j], k[0], k[1], k[2]}).second;
                              EXPECT_TRUE(fresh) << "pair " << a.id[i] << ", " << a.id[j] << " visited twice";
                          });
    });
    return found;
}

struct PeriodicCase {
    int n;
    bool merge;
    double depth;  // z period; under the support it holds images of the particle itself
};

class PeriodicSearch : public ::testing::TestWithParam<PeriodicCase> {};

TEST_P(PeriodicSearch, FindsEveryImageWithinTheSupport) {
    const PeriodicCase pc = GetParam();
    // 0.29 is no whole number of cells for any n: the cells stretch along every axis.
    const Scene s = periodic_box(0.29, pc.depth, 77u + pc.n, pc.depth < 0.1 ? 300 : 1500);
    const SearchOptions opt{pc.n, pc.merge};
    const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, pc.n, s.periodic.data());
    EXPECT_GE(double(g.view.cell_size.x), double(s.params.support) / pc.n);
    EXPECT_NEAR(g.view.nx * double(g.view.cell_size.x), 0.29, 1e-6);
    auto d = make_host_subdomain({s.params, g.view, s.kernel, true, opt}, s.size());
    d->upload(make_particle_arrays(s, g));
    d->sort_by_cell();
    const ImagePairs expected = brute_force_images(s);
    const ImagePairs found = searched_images(s, g, opt, *d);
    EXPECT_EQ(found.size(), expected.size());
    EXPECT_TRUE(found == expected);
    EXPECT_EQ(d->count_work().neighbours, expected.size());
}

INSTANTIATE_TEST_SUITE_P(AllStrategies, PeriodicSearch,
                         ::testing::Values(PeriodicCase{1, false, 0.29}, PeriodicCase{1, true, 0.29},
                                           PeriodicCase{2, false, 0.29}, PeriodicCase{2, true, 0.29},
                                           PeriodicCase{3, false, 0.29}, PeriodicCase{3, true, 0.29},
                                           PeriodicCase{4, false, 0.29}, PeriodicCase{4, true, 0.29},
                                           PeriodicCase{2, false, 0.05}, PeriodicCase{2, true, 0.05},
                                           PeriodicCase{3, false, 0.05}, PeriodicCase{3, true, 0.05}),
                         [](const auto& info) {
                             return "n" + std::to_string(info.param.n) + (info.param.merge ? "_merged" : "_cells") +
                                    (info.param.depth < 0.1 ? "_thin" : "_cube");
                         });

// A period shorter than one cell (support / n) would need a wider stencil: refused.
TEST(PeriodicSearch, PeriodShorterThanACellIsRefused) {
    const Scene s = periodic_box(0.29, 0.05, 3u, 10);  // support 0.069 m
    EXPECT_THROW(make_grid(s.lo.data(), s.hi.data(), s.params.support, 1, s.periodic.data()), InputError);
    EXPECT_NO_THROW(make_grid(s.lo.data(), s.hi.data(), s.params.support, 2, s.periodic.data()));
}

// Stored lists reach j by its minimum image: the listed forces equal the cell search's.
TEST(PeriodicSearch, VerletListsGiveTheCellSearchForces) {
    Scene s = periodic_box(0.29, 0.29, 5u, 1500);
    for (auto& v : s.velocity) v = {0.3f, -0.2f, 0.1f};
    s.params.nu = real(1e-3);
    // Cells of support + skin: what a Verlet list's stencil needs (both searches use them).
    const Grid g = make_grid(s.lo.data(), s.hi.data(), 1.1 * s.params.support, 1, s.periodic.data());
    auto forces = [&](bool listed) {
        auto d = make_host_subdomain({s.params, g.view, s.kernel, true, {1, false}}, s.size());
        d->upload(make_particle_arrays(s, g));
        d->sort_by_cell();
        d->advance(euler_step(0));
        if (listed) {
            d->build_neighbour_list(real(0.1) * s.params.support);
            d->compute_forces_listed();
        } else {
            d->compute_forces();
        }
        return d->download().force;
    };
    const auto a = forces(false), b = forces(true);
    double err = 0, norm = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double e[4] = {a[i].x - b[i].x, a[i].y - b[i].y, a[i].z - b[i].z, a[i].w - b[i].w};
        for (double x : e) err += x * x;
        norm += double(a[i].x) * a[i].x + double(a[i].y) * a[i].y + double(a[i].z) * a[i].z + double(a[i].w) * a[i].w;
    }
    EXPECT_LT(std::sqrt(err / norm), 1e-5);
}

// A uniform translation carries every particle through the faces several times; relative
// positions do not change, so neither does the neighbour set (images included).
TEST(PeriodicSearch, ParticlesCrossingAFaceKeepTheirNeighbours) {
    Scene s = periodic_box(0.29, 0.29, 11u, 1000);
    const SearchOptions opt{2, true};
    const Grid g = make_grid(s.lo.data(), s.hi.data(), s.params.support, opt.cells_per_support, s.periodic.data());
    auto d = make_host_subdomain({s.params, g.view, s.kernel, true, opt}, s.size());
    ParticleArrays a = make_particle_arrays(s, g);
    for (real4& v : a.velrho) v = {real(0.71), real(-0.43), real(0.29), v.w};
    d->upload(a);  // forces start at zero: the drift is a pure translation
    d->sort_by_cell();
    const ImagePairs before = searched_images(s, g, opt, *d);
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs_before;
    for (const auto& p : before) pairs_before.insert({std::get<0>(p), std::get<1>(p)});
    for (int k = 0; k < 40; ++k) {  // 40 x 0.03 s x 0.71 m/s = 2.9 periods along x
        d->advance(euler_step(real(0.03)));
        d->sort_by_cell();
    }
    // The images change as particles wrap, so compare pairs by id, judged at the new positions.
    Scene moved = s;
    const ParticleArrays b = d->download();
    for (std::size_t i = 0; i < b.size(); ++i) {
        const int3v c = g.view.decode(b.cell[i]);
        moved.position[b.id[i]] = {c.x * double(g.view.cell_size.x) + b.pos[i].x,
                                   c.y * double(g.view.cell_size.y) + b.pos[i].y,
                                   c.z * double(g.view.cell_size.z) + b.pos[i].z};
        for (int ax = 0; ax < 3; ++ax) {
            EXPECT_GE(moved.position[b.id[i]][ax], 0.0);
            EXPECT_LT(moved.position[b.id[i]][ax], 0.29 + 1e-6);
        }
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs_after;
    for (const auto& p : searched_images(moved, g, opt, *d)) pairs_after.insert({std::get<0>(p), std::get<1>(p)});
    EXPECT_EQ(pairs_after.size(), pairs_before.size());
    EXPECT_TRUE(pairs_after == pairs_before);
}

// A cubic lattice filling a periodic box: every particle sees the same neighbourhood, so
// forces cancel and nothing moves, with any strategy.
Scene periodic_lattice(int per_side, double dp) {
    Scene s;
    s.name = "lattice";
    s.dp = dp;
    for (int i = 0; i < per_side; ++i)
        for (int j = 0; j < per_side; ++j)
            for (int k = 0; k < per_side; ++k) {
                s.position.push_back({(i + 0.5) * dp, (j + 0.5) * dp, (k + 0.5) * dp});
                s.velocity.push_back({0, 0, 0});
            }
    s.params.h = real(std::sqrt(3.0) * dp);
    s.params.mass = real(1000 * dp * dp * dp);
    s.params.c0 = 10;
    s.params.nu = real(1e-3);
    s.params.gravity = {0, 0, 0};
    s.params = finish_params(s.params);
    s.lo = {0, 0, 0};
    s.hi = {per_side * dp, per_side * dp, per_side * dp};
    s.periodic = {true, true, true};
    return s;
}

TEST(PeriodicLattice, StaysAtRestWithEveryStrategy) {
    const Scene s = periodic_lattice(12, 0.02);
    std::vector<SearchOptions> strategies;
    for (int n = 1; n <= 4; ++n)
        for (bool merge : {false, true}) strategies.push_back({n, merge});
    SearchOptions verlet;
    verlet.verlet = true;
    strategies.push_back(verlet);
    for (const SearchOptions& st : strategies) {
        SolverOptions o;
        o.search = st;
        Simulation sim(s, o);
        for (int k = 0; k < 10; ++k) sim.step();
        const StepStats& stats = sim.step().stats;
        EXPECT_LT(std::sqrt(double(stats.max_speed2)), 1e-6 * s.params.c0) << "n " << st.cells_per_support << " merge "
                                                                          << st.merge << " verlet " << st.verlet;
        EXPECT_LT(std::sqrt(double(stats.max_accel2)), 1e-3);
        EXPECT_NEAR(double(stats.min_density), 1000.0, 1e-2);
        EXPECT_NEAR(double(stats.max_density), 1000.0, 1e-2);
        EXPECT_EQ(sim.snapshot().id.size(), s.size());
    }
}

// X slabs see the whole of y and z, so periodic y and z need nothing from the exchange.
TEST(PeriodicSubdomains, PeriodicYAndZMatchOneSubdomain) {
    Scene s = make_scene("taylor-green", {{"resolution", "16"}});
    s.periodic[0] = false;  // open in x, with room to spread
    s.lo[0] = -0.2;
    s.hi[0] = 1.2;
    SolverOptions one, two;
    two.subdomains = 2;
    Simulation a(s, one), b(s, two);
    test::step_both(a, b, 30);
    const auto pa = test::positions_by_id(a.snapshot()), pb = test::positions_by_id(b.snapshot());
    EXPECT_EQ(test::largest_fluid_difference(pa, pb, 0), 0.0);
}

TEST(PeriodicSubdomains, PeriodicXOnSeveralSubdomainsIsRefused) {
    const Scene s = make_scene("taylor-green", {{"resolution", "16"}});
    SolverOptions o;
    o.subdomains = 2;
    try {
        Simulation sim(s, o);
        FAIL() << "a periodic x on 2 subdomains ran";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--devices"), std::string::npos) << e.what();
    }
}

TEST(PeriodicSubdomains, VerletListsOnAShortPeriodAreRefused) {
    const Scene s = make_scene("taylor-green", {{"resolution", "16"}});  // z is 4 layers: under 2 supports
    SolverOptions o;
    o.search.verlet = true;
    EXPECT_THROW(Simulation(s, o), InputError);
}

}  // namespace
}  // namespace sph
