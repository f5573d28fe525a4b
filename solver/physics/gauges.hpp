#pragma once
// Gauges: what SPH users measure while a run goes (DualSPHysics' <gauges>), computed where the
// particles are, written once for both backends: the CUDA backend runs these functions in
// kernels (cuda_gauges.cu), the host backend in loops (host_subdomain.cpp).
//
// A probe is one sample point (or one body) in the grid's frame: a cell and the offset in it,
// as particles are stored (core/particle.hpp). Each backend returns, per probe, the partial
// sums of the particles it OWNS (ghosts are another subdomain's); the Simulation adds the
// subdomains' partial sums (max_height: takes their maximum) and finishes the value:
//   pressure    sum_j P_j V_j W / sum_j V_j W       (Shepard-normalised kernel interpolation,
//   velocity    sum_j v_j V_j W / sum_j V_j W        V_j = m / rho_j, over fluid j)
//   water_level sum_j m W at one point of the vertical line (the Simulation samples the line)
//   max_height  the highest fluid particle within a horizontal radius of the line
//   force       the fluid's force on a body's particles (see fluid_force_on_body)
// Particles move after the sort that built the cell ranges (up to one cell between sorts:
// a step, or a Verlet list's half skin, is less than a cell), so the stencil reaches one cell
// further than the support and every separation is taken from the particle's own cell.
#include <cmath>

#include "core/equation_of_state.hpp"
#include "core/params.hpp"
#include "core/particle.hpp"
#include "neighbours/grid.hpp"
#include "physics/interaction.hpp"

namespace sph {

enum class GaugeKind : std::uint32_t { pressure, velocity, water_level, max_height, force };

struct GaugeProbe {
    GaugeKind kind = GaugeKind::pressure;
    int3v cell{0, 0, 0};       // the point's cell (it may lie outside a grid fitted to the particles)
    real3 offset{0, 0, 0};     // the point's offset from that cell's lower corner
    real radius = 0;           // max_height: the horizontal radius around the line
    std::uint32_t body_first = 0, body_end = 0;  // force: the body's particle ids [first, end)
};

// Partial sums of one probe. pressure: v[0] = sum P V W, v[3] = sum V W; velocity: v[0..2] =
// sum v V W, v[3] = sum V W; water_level: v[0] = sum m W; max_height: v[0] = highest z from the
// grid's origin (lowest_height when none), v[3] = particles found; force: v[0..2] = force (N).
struct GaugeSum {
    double v[4] = {0, 0, 0, 0};
};
constexpr double lowest_height = -1e300;

SPH_HD GaugeSum empty_gauge_sum(GaugeKind kind) {
    GaugeSum s;
    if (kind == GaugeKind::max_height) s.v[0] = lowest_height;
    return s;
}
SPH_HD GaugeSum merge_gauge_sums(GaugeKind kind, const GaugeSum& a, const GaugeSum& b) {
    GaugeSum s;
    for (int k = 0; k < 4; ++k) s.v[k] = a.v[k] + b.v[k];
    if (kind == GaugeKind::max_height) s.v[0] = a.v[0] > b.v[0] ? a.v[0] : b.v[0];
    return s;
}

// What a gauge pass reads: the sorted particle arrays (cell_start from the last sort) and the
// subdomain's owned cells, whose particles [cell_start[owned_cell_begin],
// cell_start[owned_cell_end]) are the ones it owns.
struct GaugeInputs {
    ForceInputs particles;
    const std::uint32_t* id;
    std::uint32_t owned_cell_begin, owned_cell_end;
    SPH_HD std::uint32_t owned_begin() const { return particles.cell_start[owned_cell_begin]; }
    SPH_HD std::uint32_t owned_end() const { return particles.cell_start[owned_cell_end]; }
};

// The cells a probe visits: per axis `count` cells from `lo` (wrapped on periodic axes; on open
// axes clipped to the grid). A periodic axis shorter than the stencil is visited once whole.
struct GaugeStencil {
    int lo[3] = {0, 0, 0}, count[3] = {0, 0, 0};
    SPH_HD std::uint32_t cells() const { return std::uint32_t(count[0]) * count[1] * count[2]; }
    // The k-th cell (z fastest), as a linear cell index of the grid.
    SPH_HD std::uint32_t cell(const GridView& g, std::uint32_t k) const {
        const int z = lo[2] + int(k % std::uint32_t(count[2]));
        k /= std::uint32_t(count[2]);
        const int y = lo[1] + int(k % std::uint32_t(count[1]));
        const int x = lo[0] + int(k / std::uint32_t(count[1]));
        return g.encode(g.periodic_x ? wrap_index(x, g.nx) : x, g.periodic_y ? wrap_index(y, g.ny) : y,
                        g.periodic_z ? wrap_index(z, g.nz) : z);
    }
};

// reach[a] < 0: the whole axis.
SPH_HD GaugeStencil gauge_stencil(const GridView& g, int3v c, const int reach[3]) {
    GaugeStencil s;
    const int center[3] = {c.x, c.y, c.z}, n[3] = {g.nx, g.ny, g.nz};
    const bool periodic[3] = {g.periodic_x, g.periodic_y, g.periodic_z};
    for (int a = 0; a < 3; ++a) {
        if (reach[a] < 0 || (periodic[a] && 2 * reach[a] + 1 >= n[a])) {
            s.lo[a] = 0;
            s.count[a] = n[a];
        } else if (periodic[a]) {
            s.lo[a] = center[a] - reach[a];
            s.count[a] = 2 * reach[a] + 1;
        } else {
            const int lo = center[a] - reach[a] < 0 ? 0 : center[a] - reach[a];
            const int hi = center[a] + reach[a] >= n[a] ? n[a] - 1 : center[a] + reach[a];
            s.lo[a] = lo;
            s.count[a] = hi >= lo ? hi - lo + 1 : 0;
        }
    }
    return s;
}

// Cells along an axis that hold everything within `distance` of a point in a cell, with one
// more for particles that changed cell since the sort.
SPH_HD int gauge_reach(real distance, real cell_size) { return int(std::ceil(distance / cell_size)) + 1; }

// The stencil of a probe: the support around a point; a radius around the whole vertical line.
SPH_HD GaugeStencil probe_stencil(const GaugeProbe& probe, const GridView& g, const PhysicsParams& p) {
    const real3 cs = g.cell_size;
    if (probe.kind == GaugeKind::max_height) {
        const int reach[3] = {gauge_reach(probe.radius, cs.x), gauge_reach(probe.radius, cs.y), -1};
        return gauge_stencil(g, probe.cell, reach);
    }
    const int reach[3] = {gauge_reach(p.support, cs.x), gauge_reach(p.support, cs.y), gauge_reach(p.support, cs.z)};
    return gauge_stencil(g, probe.cell, reach);
}

// a - b for a at offset oa in cell ca and b at offset ob in cell cb (cell coordinates), the
// nearest image along periodic axes.
SPH_HD real3 cell_frame_separation(int3v ca, const real3& oa, int3v cb, const real3& ob, const GridView& g) {
    const real3 cs = g.cell_size;
    real3 r = make3(oa.x - ob.x - real(cb.x - ca.x) * cs.x, oa.y - ob.y - real(cb.y - ca.y) * cs.y,
                    oa.z - ob.z - real(cb.z - ca.z) * cs.z);
    if (g.periodic_x) r.x = nearest_image(oa.x, ob.x, cb.x - ca.x, g.nx, cs.x);
    if (g.periodic_y) r.y = nearest_image(oa.y, ob.y, cb.y - ca.y, g.ny, cs.y);
    if (g.periodic_z) r.z = nearest_image(oa.z, ob.z, cb.z - ca.z, g.nz, cs.z);
    return r;
}

// The partial sums of one probe (not force) over the owned fluid particles of one stencil cell.
template <class Kernel>
SPH_HD GaugeSum probe_cell_sum(const GaugeProbe& probe, const GaugeInputs& in, const PhysicsParams& p,
                               const Kernel& kernel, std::uint32_t c) {
    GaugeSum s = empty_gauge_sum(probe.kind);
    const ForceInputs& f = in.particles;
    const GridView& g = f.grid;
    const std::uint32_t own_lo = in.owned_begin(), own_hi = in.owned_end();
    std::uint32_t begin = f.cell_start[c], end = f.cell_start[c + 1];
    begin = begin < own_lo ? own_lo : begin;
    end = end > own_hi ? own_hi : end;
    for (std::uint32_t j = begin; j < end; ++j) {
        const real4 vr = f.velrho[j];
        if (is_boundary(vr) || f.cell[j] >= g.out_of_domain()) continue;
        const real4 pj = f.pos[j];
        const int3v cj = g.decode(f.cell[j]);
        if (probe.kind == GaugeKind::max_height) {
            const real3 r = cell_frame_separation(probe.cell, probe.offset, cj, xyz(pj), g);
            if (r.x * r.x + r.y * r.y > probe.radius * probe.radius) continue;
            const double z = double(cj.z) * double(g.cell_size.z) + double(pj.z);
            s.v[0] = z > s.v[0] ? z : s.v[0];
            s.v[3] += 1;
            continue;
        }
        const real3 r = cell_frame_separation(probe.cell, probe.offset, cj, xyz(pj), g);
        const real r2 = dot(r, r);
        if (r2 >= p.support2) continue;
        const real w = kernel.w(sqrt_r(r2));
        const real rho = density(vr);
        const double vw = double(p.mass / rho) * double(w);
        switch (probe.kind) {
        case GaugeKind::pressure:
            s.v[0] += double(tait_pressure(p, rho)) * vw;
            s.v[3] += vw;
            break;
        case GaugeKind::velocity:
            s.v[0] += double(vr.x) * vw;
            s.v[1] += double(vr.y) * vw;
            s.v[2] += double(vr.z) * vw;
            s.v[3] += vw;
            break;
        case GaugeKind::water_level: s.v[0] += double(p.mass) * double(w); break;
        default: break;
        }
    }
    return s;
}

// The force fluid particle j exerts on the probe's body (zero unless j is fluid). Dynamic
// boundary particles gather only a density rate in the force loop (their momentum is not
// computed), so the force is summed here from the pair terms the force loop applies to j:
// with a_j(i) = j's acceleration from body particle i (pressure, artificial and laminar
// viscosity: PairBody), the force on i is -m a_j(i) (the pair terms are antisymmetric). Summed
// over the OWNED fluid particles j, so that the fluid side of every pair is current; a body
// particle held as another subdomain's ghost has its density from the last exchange.
template <class Kernel>
SPH_HD real3 fluid_force_on_body(std::uint32_t j, const GaugeProbe& probe, const GaugeInputs& in,
                                 const PhysicsParams& p, const Kernel& kernel) {
    const ForceInputs& f = in.particles;
    const GridView& g = f.grid;
    real3 total = make3(0, 0, 0);
    if (f.cell[j] >= g.out_of_domain() || is_boundary(f.velrho[j])) return total;
    const PairBody<Kernel, false> body(f, p, kernel);
    const ParticleSide side_j = particle_side(f, j);
    const real3 oj = xyz(side_j.pos);
    const int3v cj = g.decode(f.cell[j]);
    const real3 cs = g.cell_size;
    const int reach[3] = {gauge_reach(p.support, cs.x), gauge_reach(p.support, cs.y), gauge_reach(p.support, cs.z)};
    const GaugeStencil st = gauge_stencil(g, cj, reach);
    const real near2 = real(1e-18) * p.support2;
    for (std::uint32_t k = 0; k < st.cells(); ++k) {
        const std::uint32_t c = st.cell(g, k);
        for (std::uint32_t i = f.cell_start[c]; i < f.cell_start[c + 1]; ++i) {
            const real4 vr_i = f.velrho[i];
            if (!is_boundary(vr_i) || f.cell[i] >= g.out_of_domain()) continue;
            const std::uint32_t id = in.id[i] & ~ghost_id_flag;
            if (id < probe.body_first || id >= probe.body_end) continue;
            const real3 rji = cell_frame_separation(cj, oj, g.decode(f.cell[i]), xyz(f.pos[i]), g);  // x_j - x_i
            const real r2 = dot(rji, rji);
            if (r2 >= p.support2 || r2 <= near2) continue;
            total -= p.mass * body.terms(side_j, i, vr_i, rji, r2).acc;
        }
    }
    return total;
}

}  // namespace sph
