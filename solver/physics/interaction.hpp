#pragma once
// The pair interaction of weakly compressible SPH, written once for both backends, in
// DualSPHysics' forms (JSphGpu_ker.cu, v5.4):
//   continuity  d rho_i/dt = sum_j m (rho_i / rho_j) (v_i - v_j) . grad W_ij   (+ delta-SPH diffusion, fluid pairs)
// The diffusion of Molteni and Colagrossi (2009) acts on the density difference less its
// hydrostatic part (Fourtakas et al. 2019, linearised: rho_i^H - rho_j^H = rho0 g . r_ij / c0^2,
// from dP = rho0 g . dr and dP/drho = c0^2 near rho0). Diffusing the whole difference would
// flatten the hydrostatic density gradient: a settled tank reads low at the floor. As in
// DualSPHysics' DensityDT 2, a fluid particle with a wall particle inside its support takes
// none of it (p.diffusion_beside_walls: its DensityDT 3 keeps it), so the diffusion is summed
// apart from the continuity term and added, or not, once the particle's pairs are done.
//   momentum    dv_i/dt    = -sum_j m ((P_i + P_j) / (rho_i rho_j) + Pi_ij) grad W_ij + g
// (with the cubic spline also Monaghan's tensile correction, as DualSPHysics: smoothing_kernels.hpp)
// with Monaghan's artificial viscosity Pi_ij, plus, when nu > 0, the laminar viscosity of
// Lo and Shao (2002) (Morris et al. 1997 with a constant nu):
//   dv_i/dt  += sum_j m 4 nu (r_ij . grad W_ij) / ((rho_i + rho_j)(r_ij^2 + eta^2)) v_ij
// which makes a Newtonian flow have the viscosity nu. Boundary particles (dynamic boundary
// conditions) gather density from fluid neighbours only and do not move.
// The dissipative terms (both viscosities and the diffusion) read the previous step's
// velocity and density: the Verlet step (integration.hpp) then applies them as forward Euler
// from step n-1, which damps. Centred on step n, a leapfrog step grows its computational
// (odd-even) mode under any damping (Durran, Numerical Methods for Fluid Dynamics, 2.4.2):
// a random particle cloud blew up within 30 steps that way.
// Particle shifting (p.shift > 0, flows without a free surface) needs the concentration
// gradient, which a pass of its own sums (particle_concentration_gradient, below).
#include "core/params.hpp"
#include "core/particle.hpp"
#include "neighbours/cell_search.hpp"

namespace sph {

// What the force loop reads: the sorted particle arrays of one subdomain.
struct ForceInputs {
    const real4* pos;
    const real4* velrho;
    const real4* velrho_prev;  // the previous step's, for the dissipative terms
    const std::uint32_t* cell;
    const std::uint32_t* cell_start;
    // First fluid particle of each cell (cell_start[c] <= fluid_begin[c] <= cell_start[c + 1]),
    // for searches that let boundary particles visit fluid only; null where no search uses it
    // (the host backend).
    const std::uint32_t* fluid_begin;
    GridView grid;
    // Each particle's cell as coordinates, kept by the integration between list rebuilds, for
    // the listed loop (the CUDA backend with Verlet lists); null elsewhere.
    const CellCoords* cell_coords;
    // Each particle's position against its cell at the last list rebuild (KeptCells), for
    // lists whose entries carry the cell offsets (NeighbourList::cell_offsets); null elsewhere.
    const real4* build_frame = nullptr;
};

// What a pair's terms read of particle i: its position (w: pressure), velocity and density,
// and the previous step's.
// 1 / rho_i is taken once here: nvcc kept a reciprocal of rho_i in every unrolled pair body.
struct ParticleSide {
    real4 pos, vr, old;
    real inv_rho;
    SPH_HD bool fluid() const { return !is_boundary(vr); }
};
SPH_HD ParticleSide particle_side(const ForceInputs& in, std::uint32_t i) {
    const real4 vr = in.velrho[i];
    return {in.pos[i], vr, in.velrho_prev[i], fast_divide(real(1), density(vr))};
}

// One pair's contribution to particle i: acceleration, d rho / dt of the continuity term, and
// the density diffusion's part of it, kept apart: a fluid pair's term, or for a wall j beside
// fluid i, under DensityDT 2, infinity, which no finite sum undoes and which drops i's whole
// diffusion at the end (PairTotals::result), as DualSPHysics' FLT_MAX does. A flag of its own
// cost the GPU's force loops a register each and made three of them spill (make perf-check).
struct PairTerms {
    real3 acc;
    real drho;
    real diffusion = 0;
};

// The pair body: the terms of one pair (i, j) inside the support that is not boundary-boundary,
// given i's side, j's velocity and density (loaded by the caller, which tested the pair) and
// the separation x_i - x_j. Boundary particles only gather density.
template <class Kernel, bool Diffusion>
struct PairBody {
    const ForceInputs& in;
    const PhysicsParams& p;
    const Kernel kernel;  // a copy (two numbers): a reference to a local made the GPU keep it on the stack
    real diffusion_coef, visc_coef, laminar_coef;
    real3 hydrostatic_drho;  // rho0 g / c0^2: d rho^H / d r

    SPH_HD PairBody(const ForceInputs& in_, const PhysicsParams& p_, const Kernel& k)
        : in(in_), p(p_), kernel(k), diffusion_coef(Diffusion ? 2 * p_.delta * p_.h * p_.c0 * p_.mass : real(0)),
          visc_coef(p_.alpha * p_.h * p_.c0), laminar_coef(4 * p_.nu * p_.mass),
          hydrostatic_drho((p_.rho0 / (p_.c0 * p_.c0)) * p_.gravity) {}

    SPH_HD_INLINE PairTerms terms(const ParticleSide& a, std::uint32_t j, const real4& vr_j, const real3& rij, real r2) const {
        return terms_with(a, j, [&] { return in.pos[j].w; }, vr_j, rij, r2);
    }
    // terms() with j's P / rho^2 (its position's w) already loaded by the caller.
    SPH_HD_INLINE PairTerms terms(const ParticleSide& a, std::uint32_t j, real pressure_j, const real4& vr_j,
                                  const real3& rij, real r2) const {
        return terms_with(a, j, [pressure_j] { return pressure_j; }, vr_j, rij, r2);
    }
    // pressure_j() gives j's P / rho^2 where the momentum term needs it: the cell searches load
    // it there (loaded first, it stayed live through the whole body, and the GPU's cell-search
    // kernels spilled: make perf-check), the listed loop passes the value it loaded.
    // The tensile correction's R of one particle from its P / rho^2 (CubicSpline).
    static SPH_HD_INLINE real tensile_part(real pressure_over_rho2) {
        return pressure_over_rho2 * (pressure_over_rho2 > 0 ? real(0.01) : real(-0.2));
    }
    template <class PressureOf>
    SPH_HD_INLINE PairTerms terms_with(const ParticleSide& a, std::uint32_t j, const PressureOf& pressure_j,
                                       const real4& vr_j, const real3& rij, real r2) const {
        const bool fluid_j = !is_boundary(vr_j);
        const real r = sqrt_r(r2);
        const real fac = kernel.grad_factor(r);
        const real rho_i = density(a.vr), rho_j = density(vr_j);
        const real inv_rho_j = fast_divide(real(1), rho_j);
        const real rho_i_over_j = rho_i * inv_rho_j;
        // m (rho_i / rho_j) (v_ij . r_ij) F, grad W = r_ij F: DualSPHysics' continuity form.
        PairTerms t{{0, 0, 0}, p.mass * fac * dot(xyz(a.vr) - xyz(vr_j), rij) * rho_i_over_j};
        if (!a.fluid()) return t;
        // Boundary particles never change velocity, and their old density is not read: skip
        // the load (walls are half of some scenes' neighbours).
        const real4 old_j = fluid_j ? in.velrho_prev[j] : vr_j;
        if (Diffusion && fluid_j) {
            const real old_rho_j = density(old_j);
            t.diffusion = fast_divide(diffusion_coef * (density(a.old) - old_rho_j - dot(hydrostatic_drho, rij)) * r2 * fac,
                                      old_rho_j * (r2 + p.eta2));
        } else if (Diffusion && !p.diffusion_beside_walls) {
            t.diffusion = real(INFINITY);
        }
        const real3 old_vij = xyz(a.old) - xyz(old_j);
        const real old_vdotr = dot(old_vij, rij);
        real pi_ij = 0;
        if (old_vdotr < 0) pi_ij = fast_divide(-visc_coef * old_vdotr, (r2 + p.eta2) * real(0.5) * (rho_i + rho_j));
        // DualSPHysics' momentum form, (P_i + P_j) / (rho_i rho_j), from the P / rho^2 each
        // particle carries: P_i/rho_i^2 (rho_i / rho_j) + P_j/rho_j^2 (rho_j / rho_i).
        const real pressure_over_rho2_j = pressure_j();
        real prs = a.pos.w * rho_i_over_j + pressure_over_rho2_j * rho_j * a.inv_rho;
        if constexpr (Kernel::tensile_correction)
            prs += kernel.tensile_weight(r) * (tensile_part(a.pos.w) + tensile_part(pressure_over_rho2_j));
        const real s = -p.mass * (prs + pi_ij) * fac;
        t.acc = s * rij;
        // A uniform runtime branch rather than a template flag: compiling the laminar term
        // out would double the force kernels' instantiations (kernel x search x diffusion)
        // and the CUDA compile time, and every thread takes the same side.
        if (p.nu > 0) t.acc += fast_divide(laminar_coef * r2 * fac, (rho_i + rho_j) * (r2 + p.eta2)) * old_vij;
        return t;
    }
};

// One particle's totals, summed pair by pair in visiting order. A wall particle's sums are
// the same bits whichever GPU loop computed its terms (add_uncontracted), since a run can
// take a wall particle through either, warp by warp (cuda_cell_forces.cu, forces_compacted_kernel);
// a fluid particle goes through one loop in a run, where the sum may fuse with the terms'
// last products (that fusion is 2-4% of the per-thread loop on an H200).
struct PairTotals {
    bool fluid_i;
    real3 acc{0, 0, 0};
    real drho = 0;
    real diffusion = 0;  // fluid i: the density diffusion, summed apart (infinite: dropped)
    SPH_HD_INLINE void accumulate(const PairTerms& t) {
        if (fluid_i) {
            drho += t.drho;
            diffusion += t.diffusion;
            acc += t.acc;
        } else {
            drho = add_uncontracted(drho, t.drho);
        }
    }
    SPH_HD real4 result(const PhysicsParams& p) const {
        if (!fluid_i) return make4(acc, drho);
        return make4(acc + p.gravity, diffusion < real(INFINITY) ? drho + diffusion : drho);
    }
};

// The sums over one particle's neighbours. add() takes one candidate j and the separation
// x_i - x_j; the search strategy (cell ranges or a stored list) only decides who is visited.
template <class Kernel, bool Diffusion>
struct PairSums {
    PairBody<Kernel, Diffusion> body;
    ParticleSide side;
    PairTotals totals;

    SPH_HD PairSums(std::uint32_t i, const ForceInputs& in, const PhysicsParams& p, const Kernel& k)
        : body(in, p, k), side(particle_side(in, i)), totals{side.fluid()} {}

    SPH_HD_INLINE void add(std::uint32_t j, const real3& rij, real r2) {
        const PhysicsParams& p = body.p;
        if (r2 >= p.support2 || r2 <= real(1e-18) * p.support2) return;  // outside, or itself
        add_neighbour(j, rij, r2);
    }
    // add() for a candidate already known to lie inside the support (and not to be i).
    SPH_HD_INLINE void add_neighbour(std::uint32_t j, const real3& rij, real r2) {
        const real4 vr_j = body.in.velrho[j];
        if (!totals.fluid_i && is_boundary(vr_j)) return;  // boundary-boundary pairs do nothing
        totals.accumulate(body.terms(side, j, vr_j, rij, r2));
    }
    // add() with j's velocity and density already loaded (the listed loop loads them with
    // j's position, before the support test, so that the two loads wait once, not in turn).
    // One test of all three conditions (bitwise, no short cut): with the wall check behind the
    // support test the compiler sank the load below it.
    SPH_HD_INLINE void add_loaded(std::uint32_t j, const real4& vr_j, const real3& rij, real r2) {
        if (outside_or_wall_pair(vr_j, r2)) return;
        totals.accumulate(body.terms(side, j, vr_j, rij, r2));
    }
    // add_loaded() with j's whole position too, whose w (P / rho^2) the pair body then takes
    // from registers instead of loading it again.
    SPH_HD_INLINE void add_loaded(std::uint32_t j, const real4& pos_j, const real4& vr_j, const real3& rij, real r2) {
        if (outside_or_wall_pair(vr_j, r2)) return;
        totals.accumulate(body.terms(side, j, pos_j.w, vr_j, rij, r2));
    }
    SPH_HD bool fluid_i() const { return totals.fluid_i; }
    SPH_HD real4 result() const { return totals.result(body.p); }

  private:
    SPH_HD_INLINE bool outside_or_wall_pair(const real4& vr_j, real r2) const {
        const PhysicsParams& p = body.p;
        return (r2 >= p.support2) | (r2 <= real(1e-18) * p.support2) | (!totals.fluid_i & is_boundary(vr_j));
    }
};

// x_i - x_j from cell-relative offsets: (cell_i - cell_j) * cs + off_i - off_j, exact in the
// cell part. (dx, dy, dz) = cell_j - cell_i, unwrapped across periodic faces.
SPH_HD real3 separation(const real4& pi, const real4& pj, int dx, int dy, int dz, const real3& cs) {
    return make3(pi.x - pj.x - dx * cs.x, pi.y - pj.y - dy * cs.y, pi.z - pj.z - dz * cs.z);
}

// One component of the minimum-image separation along a periodic axis of n cells of size cs:
// d = cell_j - cell_i as stored (wrapped), first brought to the nearest image in whole cells,
// then folded once more if the offsets put the other image closer.
SPH_HD real nearest_image(real off_i, real off_j, int d, int n, real cs) {
    if (2 * d > n) d -= n;
    else if (2 * d < -n) d += n;
    real r = off_i - off_j - d * cs;
    const real period = n * cs;
    if (2 * r > period) r -= period;
    else if (2 * r < -period) r += period;
    return r;
}

// x_i - x_j of two particles whose cells are known only as indices (stored lists): the
// plain difference on open axes, the minimum image on periodic ones (a stored list is only
// allowed when each period is at least twice the list's reach, so that image is unique).
SPH_HD real3 listed_separation(const real4& pi, const real4& pj, int3v ci, int3v cj, const GridView& g) {
    real3 r = separation(pi, pj, cj.x - ci.x, cj.y - ci.y, cj.z - ci.z, g.cell_size);
    if (g.periodic_x) r.x = nearest_image(pi.x, pj.x, cj.x - ci.x, g.nx, g.cell_size.x);
    if (g.periodic_y) r.y = nearest_image(pi.y, pj.y, cj.y - ci.y, g.ny, g.cell_size.y);
    if (g.periodic_z) r.z = nearest_image(pi.z, pj.z, cj.z - ci.z, g.nz, g.cell_size.z);
    return r;
}

// x_i - x_j for the candidates of one stencil range of cell offset (dx, dy) and, per
// candidate, dz: the same as separation() up to rounding, with the x and y cell offsets taken
// off x_i once per range rather than per candidate. Every loop that takes ranges (hit masks,
// the GPU's pair queue) forms separations through it, so they agree to the bit.
struct RangeSeparation {
    real bx, by, pz, csz;
    SPH_HD RangeSeparation(const real4& pos_i, int dx, int dy, const real3& cs)
        : bx(pos_i.x - dx * cs.x), by(pos_i.y - dy * cs.y), pz(pos_i.z), csz(cs.z) {}
    SPH_HD real3 operator()(const real4& pj, int dz) const { return make3(bx - pj.x, by - pj.y, pz - dz * csz - pj.z); }
};

// The candidates of [j0, j0 + n) (n <= 32) inside the support of a particle, one bit each.
template <class ZOffset>
SPH_HD std::uint32_t support_hits(const ForceInputs& in, const PhysicsParams& p, const RangeSeparation& sep,
                                  std::uint32_t j0, std::uint32_t n, const ZOffset& z_offset) {
    const real near2 = real(1e-18) * p.support2;
    std::uint32_t hits = 0;
    for (std::uint32_t k = 0; k < n; ++k) {
        const real3 rij = sep(in.pos[j0 + k], z_offset(j0 + k));
        const real r2 = dot(rij, rij);
        if (r2 < p.support2 && r2 > near2) hits |= std::uint32_t(1) << k;
    }
    return hits;
}

// One particle range of the stencil through the pair sums, in two passes per 32 candidates:
// the lanes test every candidate and set a bit per neighbour, then each lane runs the pair
// body over its own bits. Done candidate by candidate, a warp runs the body whenever any of
// its lanes has a neighbour there, at the few lanes that do (13-15 of 32 on an H200); by bits,
// the body runs as often as the lane with most neighbours in the chunk needs. The same
// neighbours in the same order as visit().
template <class Sums, class ZOffset>
SPH_HD void add_range_by_hit_masks(Sums& sums, const real4& pos_i, const ForceInputs& in, const PhysicsParams& p,
                                   std::uint32_t begin, std::uint32_t end, int dx, int dy, const ZOffset& z_offset) {
    const RangeSeparation sep(pos_i, dx, dy, in.grid.cell_size);
    for (std::uint32_t j0 = begin; j0 < end; j0 += 32) {
        std::uint32_t hits = support_hits(in, p, sep, j0, end - j0 < 32 ? end - j0 : 32, z_offset);
        while (hits != 0) {
            const std::uint32_t j = j0 + std::uint32_t(lowest_set_bit(hits));
            hits &= hits - 1;
            const real3 rij = sep(in.pos[j], z_offset(j));
            sums.add_neighbour(j, rij, dot(rij, rij));  // the same separation as the test's
        }
    }
}

// Returns (acceleration, d rho / dt) of particle i, visiting candidates cell by cell.
// Where the inputs give each cell's first fluid particle (in.fluid_begin: the CUDA backend), a
// boundary particle visits only the fluid of each stencil cell: the same neighbours that add()
// keeps, in the same order, without loading the walls around it (half of some scenes'
// particles are walls, most of them far from water). HitMasks (the CUDA backend) takes each
// range through add_range_by_hit_masks; the host keeps the plain loop.
template <class Kernel, class Search, bool Diffusion, bool HitMasks = false>
SPH_HD real4 particle_force(std::uint32_t i, const ForceInputs& in, const PhysicsParams& p, const Kernel& kernel) {
    PairSums<Kernel, Diffusion> sums(i, in, p, kernel);
    const real3 cs = in.grid.cell_size;
    const int3v c = in.grid.decode(in.cell[i]);
    if (!sums.fluid_i() && in.fluid_begin != nullptr) {
        Search::visit_fluid_cells(in.grid, in.cell_start, in.fluid_begin, c,
                                  [&](std::uint32_t begin, std::uint32_t end, int dx, int dy, int dz) {
                                      if constexpr (HitMasks) {
                                          add_range_by_hit_masks(sums, sums.side.pos, in, p, begin, end, dx, dy,
                                                                 [dz](std::uint32_t) { return dz; });
                                      } else {
                                          for (std::uint32_t j = begin; j < end; ++j) {
                                              const real3 rij = separation(sums.side.pos, in.pos[j], dx, dy, dz, cs);
                                              sums.add(j, rij, dot(rij, rij));
                                          }
                                      }
                                  });
    } else if constexpr (HitMasks) {
        Search::visit_ranges(in.grid, in.cell_start, c,
                             [&](std::uint32_t begin, std::uint32_t end, int dx, int dy, typename Search::RangeZ z) {
                                 add_range_by_hit_masks(sums, sums.side.pos, in, p, begin, end, dx, dy,
                                                        [&](std::uint32_t j) { return z.of(in.cell, j); });
                             });
    } else {
        Search::visit(in.grid, in.cell_start, in.cell, c, [&](std::uint32_t j, int dx, int dy, int dz) {
            const real3 rij = separation(sums.side.pos, in.pos[j], dx, dy, dz, cs);
            sums.add(j, rij, dot(rij, rij));
        });
    }
    return sums.result();
}

// Particle shifting's concentration gradient grad C_i = sum_j m / rho_j grad W_ij (xyz), in a
// pass of its own that only scenes with shifting run: summed inside the force loop, its
// registers made every force loop 5-10% slower on an H200, shifting or not.
template <class Kernel, class Search>
SPH_HD real4 particle_concentration_gradient(std::uint32_t i, const ForceInputs& in, const PhysicsParams& p,
                                            const Kernel& kernel) {
    real3 grad_c{0, 0, 0};
    const real4 pos_i = in.pos[i];
    const real3 cs = in.grid.cell_size;
    Search::visit(in.grid, in.cell_start, in.cell, in.grid.decode(in.cell[i]),
                  [&](std::uint32_t j, int dx, int dy, int dz) {
                      const real3 rij = separation(pos_i, in.pos[j], dx, dy, dz, cs);
                      const real r2 = dot(rij, rij);
                      if (r2 >= p.support2 || r2 <= real(1e-18) * p.support2) return;
                      grad_c += (p.mass / density(in.velrho[j]) * kernel.grad_factor(sqrt_r(r2))) * rij;
                  });
    return make4(grad_c, 0);
}

// A list entry that carries, besides j, the cell offset cell_j - cell_i of the rebuild (each
// axis in [-4, 3], 3 bits, over j's 23): with positions kept against the rebuild's cells
// (KeptCells::build_frame) a pair's separation needs neither particle's cell, and the listed
// loop gathers j's position and velocity-density, not its cell as well (change 12). Stencils
// of at most 3 cells a side and subdomains of fewer than 2^23 particles only (fits()).
struct ListEntry {
    static constexpr int index_bits = 23;
    static constexpr std::uint32_t index_mask = (std::uint32_t(1) << index_bits) - 1;
    static constexpr int reach_cells = 3;
    static bool fits(std::size_t particles, int stencil_cells) {
        return particles <= index_mask + std::size_t(1) && stencil_cells <= reach_cells;
    }
    SPH_HD static std::uint32_t encode(std::uint32_t j, int dx, int dy, int dz) {
        return j | (std::uint32_t(dx + 4) | std::uint32_t(dy + 4) << 3 | std::uint32_t(dz + 4) << 6) << index_bits;
    }
    SPH_HD static std::uint32_t index(std::uint32_t e) { return e & index_mask; }
    SPH_HD static int3v cell_offset(std::uint32_t e) {
        return {int((e >> index_bits) & 7) - 4, int((e >> (index_bits + 3)) & 7) - 4, int(e >> (index_bits + 6)) - 4};
    }
};

// A stored neighbour list (Verlet list) in chunks of list_chunk entries: chunk c of particle
// i is the list_chunk entries at (c * stride + i) * list_chunk, so that each particle's chunk
// is one aligned 16-byte piece a GPU lane stores and loads whole, and a warp's chunks are 512
// contiguous bytes. (With column k at k * stride + i, a lane storing alone wrote 4 bytes of a
// 32-byte sector: change 17.) Its entries are particle indices, or, with cell_offsets, ListEntry
// codes. A capacity is a multiple of list_chunk (list_capacity()).
constexpr std::uint32_t list_chunk = 4;
SPH_HD std::size_t list_slot(std::uint32_t k, std::uint32_t i, std::uint32_t stride) {
    return (std::size_t(k / list_chunk) * stride + i) * list_chunk + k % list_chunk;
}
// Room for at least `entries` entries a particle: whole chunks.
inline std::uint32_t list_capacity(std::uint32_t entries) { return (entries + list_chunk - 1) / list_chunk * list_chunk; }
struct alignas(16) ListChunk {
    std::uint32_t e[list_chunk];
};

struct NeighbourList {
    const std::uint32_t* index;
    const std::uint32_t* count;
    std::uint32_t stride;
    bool cell_offsets = false;
};

// How a backend runs the listed loop: the host's choices here; a GPU's come from its launch
// policy (backend/cuda_launch_policy.cuh), which has the same members.
//   packed_cells:    read each neighbour's cell from in.cell_coords, not by decoding in.cell
//   early_loads:     load j's velocity and density with its position, before the support test
//   whole_loads:     with early_loads, load j's position and velocity-density whole, once
//                    (load_whole), and keep them to the pair body
//   index_lookahead: load the list's entry k + L while entry k is summed (0, 1 or 2): a
//                    GPU's list is read from DRAM, one row of the warp at a time
//   chunk_loads:     load the list a chunk (list_chunk entries) at a time, the next chunk
//                    while the current one is summed (index_lookahead is then unused)
//   entry_offsets:   the entries carry the rebuild's cell offsets (ListEntry) and positions
//                    come from in.build_frame: no cell is read (open grids only)
struct ListedLoopDefaults {
    static constexpr bool packed_cells = false;
    static constexpr bool early_loads = false;
    static constexpr bool whole_loads = false;
    static constexpr int index_lookahead = 0;
    static constexpr bool chunk_loads = false;
    static constexpr bool entry_offsets = false;
};

// Choices with entry_offsets set: the loop a list with cell offsets takes.
template <class Choices>
struct WithEntryOffsets : Choices {
    static constexpr bool entry_offsets = true;
};

// The same sums over a stored list. Particles keep their cell between rebuilds only up to
// the skin, so each pair finds both cells. Periodic grids take each pair's separation to the
// nearest image (listed_separation); others skip those compares, which cost an entry as much
// as everything else before the support test (SASS of the CUDA loop: ~100 instructions an
// entry with them, ~50 without), in a loop of their own chosen once per particle.
template <class Kernel, bool Diffusion, class Choices, bool Periodic>
SPH_HD real4 listed_sums(std::uint32_t i, const ForceInputs& in, const NeighbourList& list, const PhysicsParams& p,
                         const Kernel& kernel) {
    constexpr int lookahead = Choices::index_lookahead;
    static_assert(lookahead >= 0 && lookahead <= 2, "index_lookahead is 0, 1 or 2");
    static_assert(!Choices::whole_loads || Choices::early_loads, "whole_loads are early loads");
    static_assert(!(Choices::entry_offsets && Periodic), "entries with cell offsets are for open grids");
    PairSums<Kernel, Diffusion> sums(i, in, p, kernel);
    const auto cell_of = [&](std::uint32_t k) {
        if constexpr (Choices::packed_cells) {
            const CellCoords c = in.cell_coords[k];
            return int3v{c.x, c.y, c.z};
        } else {
            return in.grid.decode(in.cell[k]);
        }
    };
    const auto entry = [&](std::uint32_t k) { return list.index[list_slot(k, i, list.stride)]; };
    const auto chunk = [&](std::uint32_t c) {
        return reinterpret_cast<const ListChunk*>(list.index)[std::size_t(c) * list.stride + i];
    };
    const int3v ci = Choices::entry_offsets ? int3v{0, 0, 0} : cell_of(i);
    const std::uint32_t n = list.count[i];
    // One entry through the pair sums.
    const auto sum_entry = [&](std::uint32_t j) SPH_LAMBDA_INLINE {
        int3v cj;  // with entry offsets: cell_j - cell_i of the rebuild (ci is zero)
        if constexpr (Choices::entry_offsets) {
            cj = ListEntry::cell_offset(j);
            j = ListEntry::index(j);
        } else {
            cj = cell_of(j);
        }
        const real4 pos_j = Choices::whole_loads ? load_whole(in.pos, j) : in.pos[j];
        real3 rij;
        if constexpr (Periodic) rij = listed_separation(sums.side.pos, pos_j, ci, cj, in.grid);
        else rij = separation(sums.side.pos, pos_j, cj.x - ci.x, cj.y - ci.y, cj.z - ci.z, in.grid.cell_size);
        if constexpr (Choices::whole_loads) sums.add_loaded(j, pos_j, load_whole(in.velrho, j), rij, dot(rij, rij));
        else if constexpr (Choices::early_loads) sums.add_loaded(j, in.velrho[j], rij, dot(rij, rij));
        else sums.add(j, rij, dot(rij, rij));
    };
    if constexpr (Choices::chunk_loads) {
        // A chunk's entries summed in an unrolled loop, each from its own register: picked
        // entry by entry through a chain of selects behind a branch (change 17), the loop took
        // 3% more instructions and 11% more time than one entry at a time two ahead.
        const std::uint32_t chunks = (n + list_chunk - 1) / list_chunk;
        ListChunk ahead = n > 0 ? chunk(0) : ListChunk{};
        for (std::uint32_t c = 0; c < chunks; ++c) {
            const ListChunk here = ahead;
            if (c + 1 < chunks) ahead = chunk(c + 1);
#ifdef __CUDA_ARCH__
#pragma unroll
#endif
            for (std::uint32_t e = 0; e < list_chunk; ++e)
                if (c * list_chunk + e < n) sum_entry(here.e[e]);
        }
        return sums.result();
    }
    std::uint32_t next1 = lookahead >= 1 && n > 0 ? entry(0) : 0;  // entries k + 1 and k + 2, loaded ahead
    std::uint32_t next2 = lookahead >= 2 && n > 1 ? entry(1) : 0;
    for (std::uint32_t k = 0; k < n; ++k) {
        std::uint32_t j;
        if constexpr (lookahead == 0) {
            j = entry(k);
        } else if constexpr (lookahead == 1) {
            j = next1;
            if (k + 1 < n) next1 = entry(k + 1);
        } else {
            j = next1;
            next1 = next2;
            if (k + 2 < n) next2 = entry(k + 2);
        }
        sum_entry(j);
    }
    return sums.result();
}

// Choices::entry_offsets takes a list with cell offsets on an open grid, whose positions are
// in.build_frame (the caller checks both).
template <class Kernel, bool Diffusion, class Choices = ListedLoopDefaults>
SPH_HD real4 particle_force_listed(std::uint32_t i, const ForceInputs& in, const NeighbourList& list,
                                   const PhysicsParams& p, const Kernel& kernel) {
    if constexpr (Choices::entry_offsets) {
        ForceInputs framed = in;
        framed.pos = in.build_frame;
        return listed_sums<Kernel, Diffusion, Choices, false>(i, framed, list, p, kernel);
    } else {
        return in.grid.any_periodic() ? listed_sums<Kernel, Diffusion, Choices, true>(i, in, list, p, kernel)
                                      : listed_sums<Kernel, Diffusion, Choices, false>(i, in, list, p, kernel);
    }
}

// Builds particle i's list: every candidate within support + skin, in visiting order. Where
// the inputs give each cell's first fluid particle (the CUDA backend), a wall particle lists
// fluid only: the force loop drops wall-wall pairs, and most walls then list nothing (half of
// the armadillo's particles are walls that never see water), so their entries cost neither
// memory nor a pass of the listed loop. The fluid comes in visit()'s order, so a wall sums
// the same pairs in the same order either way.
// Returns the true count; entries past `capacity` (a multiple of list_chunk) are not written
// (the caller grows and retries).
// CellOffsets writes ListEntry codes (open grids, stencils of at most ListEntry::reach_cells).
template <class Search, bool CellOffsets = false>
SPH_HD std::uint32_t build_particle_list(std::uint32_t i, const ForceInputs& in, real reach2, std::uint32_t* index,
                                         std::uint32_t stride, std::uint32_t capacity) {
    static_assert(!CellOffsets || Search::n <= ListEntry::reach_cells, "a stencil too wide for ListEntry");
    std::uint32_t n = 0;
    const real4 pi = in.pos[i];
    const real3 cs = in.grid.cell_size;
    const auto keep = [&](std::uint32_t j, int dx, int dy, int dz) {
        if (j == i) return;
        const real3 rij = separation(pi, in.pos[j], dx, dy, dz, cs);
        if (dot(rij, rij) >= reach2) return;
        if (n < capacity) index[list_slot(n, i, stride)] = CellOffsets ? ListEntry::encode(j, dx, dy, dz) : j;
        ++n;
    };
    const int3v c = in.grid.decode(in.cell[i]);
    if (in.fluid_begin != nullptr && is_boundary(in.velrho[i]))
        Search::visit_fluid_cells(in.grid, in.cell_start, in.fluid_begin, c,
                                  [&](std::uint32_t begin, std::uint32_t end, int dx, int dy, int dz) {
                                      for (std::uint32_t j = begin; j < end; ++j) keep(j, dx, dy, dz);
                                  });
    else
        Search::visit(in.grid, in.cell_start, in.cell, c, keep);
    return n;
}

// Work counters of one particle's search (candidates visited, real neighbours, ranges visited).
struct SearchWork {
    unsigned long long candidates = 0, neighbours = 0, ranges = 0;
};

template <class Search>
SPH_HD SearchWork particle_search_work(std::uint32_t i, const ForceInputs& in, const PhysicsParams& p) {
    SearchWork w;
    const real3 off_i = xyz(in.pos[i]);
    const real3 cs = in.grid.cell_size;
    const int3v c = in.grid.decode(in.cell[i]);
    Search::visit(in.grid, in.cell_start, in.cell, c, [&](std::uint32_t j, int dx, int dy, int dz) {
        const real4 pj = in.pos[j];
        const real3 rij = make3(off_i.x - pj.x - dx * cs.x, off_i.y - pj.y - dy * cs.y, off_i.z - pj.z - dz * cs.z);
        const real r2 = dot(rij, rij);
        ++w.candidates;
        if (r2 < p.support2 && r2 > real(1e-18) * p.support2) ++w.neighbours;
    });
    // Ranges visited: one per cell (or per merged z-run piece) of the stencil in the grid.
    w.ranges = Search::ranges(in.grid, c);
    return w;
}

}  // namespace sph
