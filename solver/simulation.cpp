#include "simulation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "backend/nvtx_range.hpp"
#include "core/equation_of_state.hpp"

namespace sph {

ParticleArrays make_particle_arrays(const Scene& s, const Grid& g) {
    ParticleArrays a;
    const std::size_t n = s.size();
    a.pos.resize(n);
    a.velrho.resize(n);
    a.cell.resize(n);
    a.id.resize(n);
    const double cs = g.view.cell_size;
    const int dims[3] = {g.view.nx, g.view.ny, g.view.nz};
    for (std::size_t i = 0; i < n; ++i) {
        int c[3];
        double off[3];
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
            const double rel = s.position[i][k] - g.origin[k];
            c[k] = int(std::floor(rel / cs));
            off[k] = rel - c[k] * cs;
            inside = inside && c[k] >= 0 && c[k] < dims[k];
        }
        const bool boundary = i < s.n_boundary;
        const double rho = s.density.empty() ? s.params.rho0 : s.density[i];
        a.pos[i] = {real(off[0]), real(off[1]), real(off[2]), 0};
        a.velrho[i] = make_velrho(make3(s.velocity[i][0], s.velocity[i][1], s.velocity[i][2]), real(rho), boundary);
        a.cell[i] = inside ? g.view.encode(c[0], c[1], c[2]) : g.view.out_of_domain();
        a.id[i] = std::uint32_t(i);
    }
    return a;
}

Simulation::Simulation(const Scene& scene, const SolverOptions& options) : scene_(scene), options_(options) {
    if (options_.cfl <= 0) options_.cfl = scene_.cfl;
    grid_ = make_grid(scene_.lo.data(), scene_.hi.data(), scene_.params.support, options_.search.cells_per_support);
    if (double(grid_.view.nx) * grid_.view.ny * grid_.view.nz > 4.0e9)
        throw InputError("the domain of scene '" + scene_.name + "' needs more than 4e9 cells; use fewer cells per support");
    SubdomainConfig cfg{scene_.params, grid_.view, scene_.kernel,
                        options_.diffusion && scene_.params.delta > 0, options_.search};
    const std::size_t n = scene_.size();
    n_total_ = n;
    n_fluid_ = scene_.fluid_count();
    if (options_.backend == BackendKind::cuda) subdomains_.push_back(make_cuda_subdomain(cfg, n, options_.device));
    else subdomains_.push_back(make_host_subdomain(cfg, n));
    nvtx_name_device(0, subdomains_.front()->device_name().c_str());
    subdomains_.front()->upload(make_particle_arrays(scene_, grid_));
    // Positions now live on the subdomain; keep the scene's metadata only.
    scene_.position = {};
    scene_.velocity = {};
    scene_.density = {};

    const PhysicsParams& p = scene_.params;
    limits_.max_speed = real(options_.max_speed_factor * p.c0);
    limits_.min_density = real(0.5 * p.rho0);
    limits_.max_density = real(2.0 * p.rho0);

    // Prime the loop: P / rho^2 for the initial density, then the forces of the initial state.
    Subdomain& d = *subdomains_.front();
    d.sort_by_cell();
    d.kick_drift(0, 0);
    if (options_.search.verlet) d.build_neighbour_list(verlet_skin());
    options_.search.verlet ? d.compute_forces_listed() : d.compute_forces();
    record_.stats = d.reduce_stats(0, limits_);
    d.clock().collect();
}

double Simulation::next_dt() const {
    if (options_.fixed_dt > 0) return options_.fixed_dt;
    const PhysicsParams& p = scene_.params;
    const double amax = std::sqrt(double(record_.stats.max_accel2));
    const double vmax = std::sqrt(double(record_.stats.max_speed2));
    double dt = p.h / (p.c0 + vmax);
    if (amax > 0) dt = std::min(dt, std::sqrt(p.h / amax));
    return options_.cfl * dt;
}

const StepRecord& Simulation::step() {
    Subdomain& d = *subdomains_.front();
    const double dt = next_dt();
    const real half = real(0.5 * dt);
    const long n = record_.step + 1;
    PhaseClock& clock = d.clock();
    {
        ScopedPhase ph(clock, Phase::integrate, n, 0);
        d.kick_drift(half, real(dt));
    }
    const bool verlet = options_.search.verlet;
    if (!verlet || verlet_list_expired(dt)) {
        ScopedPhase ph(clock, Phase::neighbour_list, n, 0);
        d.sort_by_cell();
        if (verlet) {
            d.build_neighbour_list(verlet_skin());
            steps_since_build_ = 0;
            moved_since_build_ = 0;
            ++list_builds_;
        }
    }
    ++steps_since_build_;
    {
        ScopedPhase ph(clock, Phase::forces, n, 0);
        verlet ? d.compute_forces_listed() : d.compute_forces();
    }
    StepStats stats;
    {
        ScopedPhase ph(clock, Phase::diagnostics, n, 0);
        stats = d.reduce_stats(half, limits_);
    }
    if (stats.bad_id != 0xffffffffu) {
        static const char* what[] = {"", "a non-finite acceleration or density rate", "a speed above the limit",
                                     "a density outside the limits"};
        std::ostringstream m;
        m << "the run blew up at step " << n << " (t = " << record_.time + dt << " s): particle " << stats.bad_id
          << " has " << what[std::min<std::uint32_t>(stats.bad_what, 3)] << " (speed limit " << limits_.max_speed
          << " m/s, density limits " << limits_.min_density << " to " << limits_.max_density << " kg/m^3)";
        SnapshotData last = snapshot();
        last.step = n;
        throw BlowUpError(m.str(), std::move(last));
    }
    {
        ScopedPhase ph(clock, Phase::integrate, n, 0);
        d.kick(half);
    }
    record_.phase_ms = clock.collect();
    record_.step = n;
    record_.time += dt;
    record_.dt = dt;
    record_.stats = stats;
    record_.out_of_domain = n_fluid_ - stats.fluid_count;
    return record_;
}

real Simulation::verlet_skin() const { return real(options_.search.skin * scene_.params.support); }

// The lists hold while no two particles can have closed the skin: each has moved at most
// sum of dt |v| since the build, bounded from the step statistics (no per-particle state).
bool Simulation::verlet_list_expired(double dt) {
    const SearchOptions& s = options_.search;
    if (s.rebuild_every > 0) return steps_since_build_ >= s.rebuild_every;
    const double vmax = std::sqrt(double(record_.stats.max_speed2));
    const double amax = std::sqrt(double(record_.stats.max_accel2));
    moved_since_build_ += dt * (vmax + 0.5 * dt * amax);
    return moved_since_build_ > 0.5 * verlet_skin();
}

WorkCounters Simulation::count_work() { return subdomains_.front()->count_work(); }

std::size_t Simulation::neighbour_list_bytes() const {
    std::size_t b = 0;
    for (const auto& d : subdomains_) b += d->neighbour_list_bytes();
    return b;
}

std::size_t Simulation::bytes_allocated() const {
    std::size_t b = 0;
    for (const auto& d : subdomains_) b += d->bytes_allocated();
    return b;
}

SnapshotData Simulation::to_snapshot(const ParticleArrays& a) const {
    SnapshotData s;
    s.time = record_.time;
    s.step = record_.step;
    const std::size_t n = a.size();
    s.position.resize(3 * n);
    s.velocity.resize(3 * n);
    s.density.resize(n);
    s.pressure.resize(n);
    s.type.resize(n);
    s.id.resize(n);
    const double cs = grid_.view.cell_size;
    for (std::size_t i = 0; i < n; ++i) {
        const bool out = a.cell[i] >= grid_.view.out_of_domain();
        const int3v c = out ? int3v{0, 0, 0} : grid_.view.decode(a.cell[i]);
        const int cc[3] = {c.x, c.y, c.z};
        const real off[3] = {a.pos[i].x, a.pos[i].y, a.pos[i].z};
        for (int k = 0; k < 3; ++k)
            s.position[3 * i + k] = out ? std::nan("") : grid_.origin[k] + cc[k] * cs + double(off[k]);
        s.velocity[3 * i + 0] = float(a.velrho[i].x);
        s.velocity[3 * i + 1] = float(a.velrho[i].y);
        s.velocity[3 * i + 2] = float(a.velrho[i].z);
        const real rho = density(a.velrho[i]);
        s.density[i] = float(rho);
        s.pressure[i] = float(tait_pressure(scene_.params, rho));
        s.type[i] = is_boundary(a.velrho[i]) ? 1 : 0;
        s.id[i] = a.id[i];
    }
    return s;
}

SnapshotData Simulation::snapshot() { return to_snapshot(subdomains_.front()->download()); }

}  // namespace sph
