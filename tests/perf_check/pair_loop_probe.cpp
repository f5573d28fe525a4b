// Host probe for the perf-check tests: the real force loop (particle_force on the pair body of
// physics/interaction.hpp) over a fixed lattice, with the stand-ins of pair_probe.hpp, so that a
// test can count its instructions with and without an injected cost. Prints a checksum so that
// the loop cannot be optimised away.
#include <algorithm>
#include <cstdio>
#include <numeric>
#include <vector>

#include "pair_probe.hpp"

namespace sph::probe {
namespace {

struct Lattice {
    std::vector<real4> pos, velrho, velrho_prev;
    std::vector<std::uint32_t> cell, cell_start;
    GridView grid;
};

// A cube of side^3 fluid particles spaced dp, with a little shear so that every term of the pair
// body (viscosity included) does work; binned and sorted by cell, positions cell-relative.
Lattice make_lattice(int side, real dp, real support) {
    Lattice l;
    l.grid.nx = l.grid.ny = l.grid.nz = std::max(1, int(side * dp / (support / 2)) + 1);
    const real cs = support / 2;  // two cells per support, as ProbeSearch
    l.grid.cell_size = {cs, cs, cs};
    struct Particle {
        std::uint32_t cell;
        real4 pos, velrho;
    };
    std::vector<Particle> ps;
    for (int x = 0; x < side; ++x)
        for (int y = 0; y < side; ++y)
            for (int z = 0; z < side; ++z) {
                const real px = (x + real(0.5)) * dp, py = (y + real(0.5)) * dp, pz = (z + real(0.5)) * dp;
                const int cx = int(px / cs), cy = int(py / cs), cz = int(pz / cs);
                const real rho = 1000 + real(0.01) * z;
                ps.push_back({l.grid.encode(cx, cy, cz),
                              {px - cx * cs, py - cy * cs, pz - cz * cs, real(1e3) / (rho * rho)},
                              {real(0.01) * pz, 0, real(-0.005) * px, rho}});
            }
    std::stable_sort(ps.begin(), ps.end(), [](const Particle& a, const Particle& b) { return a.cell < b.cell; });
    for (const auto& p : ps) {
        l.cell.push_back(p.cell);
        l.pos.push_back(p.pos);
        l.velrho.push_back(p.velrho);
    }
    l.velrho_prev = l.velrho;
    l.cell_start.assign(l.grid.cell_count() + 1, 0);
    std::uint32_t j = 0;
    for (std::uint32_t c = 0; c <= l.grid.cell_count(); ++c) {
        while (j < l.cell.size() && l.cell[j] < c) ++j;
        l.cell_start[c] = j;
    }
    return l;
}

// Not inlined, so that callgrind can count this function alone (--toggle-collect).
__attribute__((noinline)) double probe_force_loop(const Lattice& l, const PhysicsParams& p, int repeats) {
    const ForceInputs in{l.pos.data(), l.velrho.data(), l.velrho_prev.data(), l.cell.data(), l.cell_start.data(),
                          nullptr, l.grid, nullptr};
    const ProbeKernel kernel(p.h);
    double checksum = 0;
    for (int r = 0; r < repeats; ++r)
        for (std::uint32_t i = 0; i < l.pos.size(); ++i) {
            const real4 f = particle_force<ProbeKernel, ProbeSearch, true>(i, in, p, kernel);
            checksum += double(f.x) + f.y + f.z + f.w;
        }
    return checksum;
}

}  // namespace
}  // namespace sph::probe

int main() {
    using namespace sph;
    const real dp = real(0.02);
    PhysicsParams p;
    p.h = real(1.3) * dp;
    p.mass = 1000 * dp * dp * dp;
    p.c0 = 20;
    p.nu = real(1e-6);
    p = finish_params(p);
    const probe::Lattice lattice = probe::make_lattice(16, dp, p.support);
    std::printf("checksum %.9g\n", probe::probe_force_loop(lattice, p, 2));
    return 0;
}
