#include "simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

#include "backend/nvtx_range.hpp"
#include "core/equation_of_state.hpp"
#include "multi/gpu_choice.hpp"

namespace sph {

ParticleArrays make_particle_arrays(const Scene& s, const Grid& g) {
    ParticleArrays a;
    const std::size_t n = s.size();
    a.pos.resize(n);
    a.velrho.resize(n);
    a.cell.resize(n);
    a.id.resize(n);
    const double cs[3] = {g.view.cell_size.x, g.view.cell_size.y, g.view.cell_size.z};
    const int dims[3] = {g.view.nx, g.view.ny, g.view.nz};
    const bool periodic[3] = {g.view.periodic_x, g.view.periodic_y, g.view.periodic_z};
    for (std::size_t i = 0; i < n; ++i) {
        int c[3];
        double off[3];
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
            const double rel = s.position[i][k] - g.origin[k];
            c[k] = int(std::floor(rel / cs[k]));
            off[k] = rel - c[k] * cs[k];
            if (periodic[k]) c[k] = wrap_index(c[k], dims[k]);  // a point outside the period is its image
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
    if (scene_.params.shift > 0 && options_.search.verlet)
        throw InputError("scene '" + scene_.name + "' shifts particles (option 'shifting'), which needs the cell " +
                         "search; drop --verlet or set shifting=0");
    if (options_.euler_every < 1)
        throw InputError("euler_every must be at least 1 (every k-th step an Euler step), got " +
                         std::to_string(options_.euler_every));
    std::array<double, 3> lo = scene_.lo, hi = scene_.hi;
    if (options_.grid_fits_particles && scene_.size() > 0) {
        // Periodic axes keep the whole period: the wrap is defined on the scene's domain.
        std::array<double, 3> plo = scene_.position.front(), phi = plo;
        for (const auto& x : scene_.position)
            for (int k = 0; k < 3; ++k) {
                plo[k] = std::min(plo[k], x[k]);
                phi[k] = std::max(phi[k], x[k]);
            }
        for (int k = 0; k < 3; ++k) {
            if (scene_.periodic[k]) continue;
            lo[k] = std::max(lo[k], plo[k] - double(scene_.params.support));
            hi[k] = std::min(hi[k], phi[k] + double(scene_.params.support));
        }
    }
    grid_ = make_grid(lo.data(), hi.data(), search_reach(scene_.params.support, options_.search),
                      options_.search.cells_per_support,
                      scene_.periodic.data());
    check_periodic_options();
    if (double(grid_.view.nx) * grid_.view.ny * grid_.view.nz > 4.0e9)
        throw InputError("the domain of scene '" + scene_.name + "' needs more than 4e9 cells; use fewer cells per support");
    n_total_ = scene_.size();
    n_fluid_ = scene_.fluid_count();
    make_subdomains(make_particle_arrays(scene_, grid_));
    // Positions now live on the subdomains; keep the scene's metadata only.
    scene_.position = {};
    scene_.velocity = {};
    scene_.density = {};

    const PhysicsParams& p = scene_.params;
    limits_.max_speed = real(options_.max_speed_factor * p.c0);
    limits_.min_density = real(0.5 * p.rho0);
    limits_.max_density = real(2.0 * p.rho0);

    // Prime the loop: P / rho^2 for the initial density, then the forces of the initial state.
    for (auto& d : subdomains_) {
        d->sort_by_cell();
        d->advance(euler_step(0));
    }
    domain_->exchange(subdomains_);
    if (options_.search.verlet) domain_->plan_refresh(subdomains_);  // the lists below are built on this state
    std::vector<StepStats> local_stats;
    for (auto& d : subdomains_) {
        if (options_.search.verlet) d->build_neighbour_list(verlet_skin());
        options_.search.verlet ? d->compute_forces_listed() : d->compute_forces();
        local_stats.push_back(d->reduce_stats(euler_step(0), limits_));
        d->clock().collect();
    }
    record_.stats = gather_stats(local_stats);
    if (options_.search.verlet) rebuild_next_ = verlet_list_expired(record_.dt, record_.stats);
    // The overlapped path reads the slices after each sort; with lists the first step may
    // not sort (without them every step reads its own).
    if (options_.search.verlet && domain_->overlapping()) domain_->read_slices(subdomains_);
}

// What periodic axes cannot be combined with, refused before anything is allocated.
void Simulation::check_periodic_options() const {
    if (scene_.periodic[0] && options_.subdomains > 1)
        throw InputError("scene '" + scene_.name + "' is periodic in x, which runs on one subdomain only (subdomains " +
                         "are X slabs); set the number of devices (--devices) to 1");
    if (!options_.search.verlet) return;
    // A stored list keeps j, not which image of j: each period must hold at most one image
    // within the list's reach.
    const double reach = (1 + options_.search.skin) * scene_.params.support;
    static const char* axis[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        const double period = scene_.hi[a] - scene_.lo[a];
        if (scene_.periodic[a] && period < 2 * reach) {
            std::ostringstream m;
            m << "Verlet lists need each periodic axis to be at least 2 (support + skin) = " << 2 * reach
              << " m long, but scene '" << scene_.name << "' is " << period << " m long in " << axis[a]
              << "; drop --verlet (use a cell search) or lengthen the periodic box";
            throw InputError(m.str());
        }
    }
}

void Simulation::make_subdomains(const ParticleArrays& all) {
    const int n = options_.subdomains;
    if (n > 1 && !options_.device_map.empty() && int(options_.device_map.size()) != n)
        throw InputError("the device map names " + std::to_string(options_.device_map.size()) + " GPUs for " +
                         std::to_string(n) + " subdomains");
    RankGroup& ranks = options_.ranks ? *options_.ranks : process_ranks();
    // Refused here, before anything is allocated: GPU-direct that cannot be had.
    const RankTransportChoice rank_transport = choose_rank_transport(
        options_.backend, ranks.size(), options_.gpu_direct, ranks.cuda_aware(), ranks.library());
    // Refused here too, before the slabs and any GPU memory: GPUs this rank does not have, or
    // shares unasked.
    const std::vector<int> gpus = options_.backend == BackendKind::cuda
                                      ? subdomain_gpus(ranks, SubdomainPlacement(std::max(n, 1), ranks.size()))
                                      : std::vector<int>{};
    // Slabs of about the same number of particles each; a slab keeps ghost-depth slices.
    domain_ = std::make_unique<SlabDomain>(grid_.view, n, options_.search.cells_per_support, options_.balancer, all,
                                           ranks, options_.overlap);
    const SubdomainConfig cfg{scene_.params, grid_.view, scene_.kernel, options_.diffusion && scene_.params.delta > 0,
                              options_.search, false, options_.variants, all.size()};
    // One subdomain holds everything; a slab needs room for what balancing gives it, plus ghosts.
    const std::size_t capacity = n == 1 ? all.size() : all.size() + all.size() / 4 + 1024;
    // One subdomain uploads `all` itself (no copy of a large scene).
    std::vector<ParticleArrays> parts = domain_->split() ? domain_->local_parts(all) : std::vector<ParticleArrays>(1);
    for (int d = 0; d < int(parts.size()); ++d) {
        const int g = domain_->first_local() + d;
        if (options_.backend == BackendKind::host) subdomains_.push_back(make_host_subdomain(cfg, capacity));
        else subdomains_.push_back(make_cuda_subdomain(cfg, capacity, gpus[d]));
        subdomains_.back()->upload(domain_->split() ? parts[d] : all);
        parts[d] = {};
        const std::string label = n == 1 ? subdomains_.back()->device_name()
                                         : "subdomain " + std::to_string(g) + " on " + subdomains_.back()->device_name();
        nvtx_name_device(d, label.c_str());
    }
    domain_->connect(subdomains_, options_.transport, rank_transport);
}

// The GPU of each of this rank's subdomains (multi/gpu_choice.hpp): --gpu for one subdomain
// without a device map; else the map, or this rank's share of its node's GPUs.
std::vector<int> Simulation::subdomain_gpus(RankGroup& ranks, const SubdomainPlacement& placement) const {
    if (options_.subdomains == 1 && options_.device_map.empty()) return {options_.device};
    GpuChoiceInput in;
    in.rank = ranks.rank();
    in.ranks = ranks.size();
    in.first_subdomain = placement.first(ranks.rank());
    in.subdomains = placement.count(ranks.rank());
    in.local_rank = ranks.local_rank();
    in.ranks_on_node = ranks.local_size();
    in.gpus_visible = cuda_device_count();
    in.device_map = options_.device_map;
    in.share = options_.share_gpus;
    return choose_gpus(in);
}

double Simulation::next_dt() const {
    if (options_.fixed_dt > 0) return options_.fixed_dt;
    const PhysicsParams& p = scene_.params;
    const double amax = std::sqrt(double(record_.stats.max_accel2));
    const double vmax = std::sqrt(double(record_.stats.max_speed2));
    double dt = p.h / (p.c0 + vmax);
    if (amax > 0) dt = std::min(dt, std::sqrt(p.h / amax));
    if (p.nu > 0) dt = std::min(dt, 0.125 * double(p.h) * p.h / p.nu);  // viscous diffusion (Morris et al. 1997)
    return options_.cfl * dt;
}

const StepRecord& Simulation::step() {
    const auto wall_start = std::chrono::steady_clock::now();
    const double dt = next_dt();
    const long n = record_.step + 1;
    // The first step, and every euler_every-th after it, is an Euler step (integration.hpp).
    TimeStep rule = (n - 1) % options_.euler_every == 0 ? euler_step(real(dt)) : verlet_step(real(dt), real(record_.dt));
    rule.shift_speed = real(std::sqrt(double(record_.stats.max_speed2)));
    const int count = int(subdomains_.size());
    record_.slices_moved = 0;
    record_.exchange = {};
    const bool overlap = domain_->overlapping();
    const bool verlet = options_.search.verlet;
    // Without lists every step sorts and exchanges whole particles. With lists only a rebuild
    // does (the lists are built on the exchanged state); between rebuilds each particle keeps
    // its slot, an owner keeps the particles that crossed its slab's faces, and the ghosts
    // are refreshed in place. Whether this step rebuilds was decided at the end of the last
    // one, whose overlapped exchange was then a whole one (settled here) or a refresh.
    const bool rebuild = !verlet || rebuild_next_;
    if (rebuild) displacement_since_sort_ = 0;
    // With one slab there is nothing to drop or balance (the SlabDomain calls would do
    // nothing); the test only keeps two empty phases off the timeline.
    if (overlap) {
        settle_exchange(n);
    } else if (domain_->split() && rebuild) {
        // The exchange later in the step needs every particle held once: drop the stale
        // ghosts first (a move on the device).
        for (int d = 0; d < count; ++d) {
            ScopedPhase ph(clock(d), Phase::migrate, n, d);
            domain_->drop_ghosts(d, *subdomains_[d]);
        }
        // Moves slab boundaries from the previous step's update times (paper section 5.2);
        // with lists only where they are rebuilt, since a move changes owners.
        ScopedPhase ph(host_clock_, Phase::balance, n, 0);
        record_.slices_moved = domain_->rebalance(subdomains_, repartition_number(n), last_update_times());
    }
    // The forces are taken where the previous step's update (over record_.dt) left particles.
    if (!overlap && rebuild)
        for (int d = 0; d < count; ++d) {
            ScopedPhase ph(clock(d), Phase::neighbour_list, n, d);
            subdomains_[d]->sort_by_cell();
        }
    if (overlap) {
        // The balancer's counts and the boundary slices' ranges, of the sort just made.
        if (rebuild) domain_->read_slices(subdomains_);
    } else {
        rebuild ? exchange_particles(n) : refresh_ghosts(n);
    }
    if (verlet && rebuild) {
        // The refresh plan reads the cell ranges of the exchange's sort (before the builds are
        // queued: on a GPU its read-back would otherwise wait for them, inside this phase).
        {
            ScopedPhase ph(host_clock_, Phase::exchange, n, 0);
            domain_->plan_refresh(subdomains_);
        }
        // After the exchange: a subdomain lists its ghosts too.
        for (int d = 0; d < count; ++d) {
            ScopedPhase ph(clock(d), Phase::neighbour_list, n, d);
            subdomains_[d]->build_neighbour_list(verlet_skin());
        }
        steps_since_build_ = 0;
        moved_since_build_ = 0;
        ++list_builds_;
    }
    ++steps_since_build_;
    for (int d = 0; d < count; ++d) {
        ScopedPhase ph(clock(d), Phase::forces, n, d);
        verlet ? subdomains_[d]->compute_forces_listed() : subdomains_[d]->compute_forces();
    }
    // The repartition delayed into the update (paper 5.3): decided on the host while the
    // forces run (with lists after the diagnostics, and only before a rebuild: a move changes
    // owners), from the previous step's times (scaled to the particles each subdomain owns
    // now: the last move has taken effect since they were measured); its slices travel with
    // this step's exchange.
    auto decide_balance = [&] {
        ScopedPhase ph(host_clock_, Phase::balance, n, 0);
        record_.slices_moved =
            domain_->decide_balance(repartition_number(n), last_update_times(), record_.subdomain_particles);
    };
    if (overlap && !verlet) decide_balance();
    std::vector<StepStats> local_stats;
    for (int d = 0; d < count; ++d) {
        ScopedPhase ph(clock(d), Phase::diagnostics, n, d);
        local_stats.push_back(subdomains_[d]->reduce_stats(rule, limits_));
    }
    const StepStats stats = gather_stats(local_stats);
    if (stats.bad_id != 0xffffffffu) {
        static const char* what[] = {"", "a non-finite acceleration or density rate", "a speed above the limit",
                                     "a density outside the limits"};
        static const char* quantity[] = {"", "acceleration", "speed", "density"};
        const std::uint32_t kind = std::min<std::uint32_t>(stats.bad_what, 3);
        std::ostringstream m;
        m << "the run blew up at step " << n << " (t = " << record_.time + dt << " s): particle " << stats.bad_id
          << " has " << what[kind] << " (speed limit " << limits_.max_speed
          << " m/s, density limits " << limits_.min_density << " to " << limits_.max_density << " kg/m^3)";
        SnapshotData last = snapshot();
        last.step = n;
        throw BlowUpError(m.str(), std::move(last), n, stats.bad_id, quantity[kind]);
    }
    if (verlet) rebuild_next_ = verlet_list_expired(dt, stats);
    if (overlap) {
        if (verlet && rebuild_next_) decide_balance();
        advance_overlapped(rule, stats, n);
    } else {
        for (int d = 0; d < count; ++d) {
            ScopedPhase ph(clock(d), Phase::integrate, n, d);
            subdomains_[d]->advance(rule);
        }
    }
    std::vector<PhaseTimes> local_ms;
    std::vector<std::size_t> local_particles;
    for (int d = 0; d < count; ++d) {
        local_ms.push_back(clock(d).collect());
        local_particles.push_back(domain_->split() ? subdomains_[d]->active_count() : stats.fluid_count);
    }
    gather_record(local_ms, local_particles);
    const PhaseTimes host = host_clock_.collect();
    record_.transfer_ms = host[std::size_t(Phase::exchange)];
    if (overlap && options_.timing) {
        const double on_device = domain_->last_transfer_ms();  // waits for the copies
        if (on_device >= 0) record_.transfer_ms = on_device;
    }
    // Phase times overlap where the host waits for device work launched in an earlier phase;
    // the wall clock of the whole step (the subdomain clocks above have synchronised) does not.
    record_.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
    for (Phase p : {Phase::exchange, Phase::balance}) record_.phase_ms[std::size_t(p)] += host[std::size_t(p)];
    record_.step = n;
    record_.time += dt;
    record_.dt = dt;
    record_.stats = stats;
    record_.out_of_domain = n_fluid_ - stats.fluid_count;
    return record_;
}

// One exchange between subdomains, timed. When timing, the host clock runs from idle devices
// to idle devices, so that the phase holds the exchange (and its sort) and nothing queued before
// it; profiling passes (timing off) skip those two waits.
template <class Exchange>
void Simulation::timed_exchange(long step, Exchange exchange) {
    if (!domain_->split()) return;
    auto wait_for_devices = [&] {
        if (options_.timing)
            for (auto& d : subdomains_) d->synchronize();
    };
    wait_for_devices();
    ScopedPhase ph(host_clock_, Phase::exchange, step, 0);
    record_.exchange = exchange();
    wait_for_devices();
}

// Migration (particles that left their slab, slices the balancer moved) and the ghost
// refresh, in one exchange.
void Simulation::exchange_particles(long step) {
    timed_exchange(step, [&] { return domain_->exchange(subdomains_); });
}

// Verlet lists between rebuilds: each ghost gets its owner's state after the last update,
// in the slot the lists hold it in.
void Simulation::refresh_ghosts(long step) {
    timed_exchange(step, [&] { return domain_->refresh(subdomains_); });
}

// Paper section 5.3: the exchange the last step issued has arrived (the streams wait for it);
// each subdomain drops its stale ghosts, appends what it needs of what arrived and sorts. The
// state is then the one exchange_particles leaves, bitwise. Nothing to do before the first
// step: the constructor exchanged.
void Simulation::settle_exchange(long step) {
    if (!domain_->exchange_in_flight()) return;
    for (int d = 0; d < int(subdomains_.size()); ++d) {
        {
            ScopedPhase ph(clock(d), Phase::migrate, step, d);
            domain_->drop_ghosts(d, *subdomains_[d]);
        }
        ScopedPhase ph(clock(d), Phase::neighbour_list, step, d);
        domain_->settle(d, *subdomains_[d]);
    }
    record_.exchange = domain_->settled();
}

// The update of paper section 5.3: every subdomain's boundary slices (all a neighbour may need
// after this update: its ghosts and every particle that may migrate to it) first, then the
// inner slices, while the boundary slices travel (on the CUDA backend on the transport's own
// streams, ordered after the boundary update by events; the inner update is queued before the
// exchange is issued, so a transport that waits on the host does not hold it back).
void Simulation::advance_overlapped(const TimeStep& rule, const StepStats& stats, long step) {
    // How far any particle can move in this update (integration.hpp): dt |v| + dt^2 / 2 |a|,
    // plus a shift of at most dt U. |v| is the largest fluid speed now (the last step's
    // statistics are of the state it produced), |a| this step's. Summed since the last sort:
    // the boundary slices are index ranges of that sort (with lists, several steps back).
    const double dt = rule.dt;
    const double vmax = std::sqrt(double(record_.stats.max_speed2));
    const double shift = scene_.params.shift > 0 ? dt * double(rule.shift_speed) : 0.0;
    displacement_since_sort_ += dt * vmax + 0.5 * dt * dt * std::sqrt(double(stats.max_accel2)) + shift;
    // Between list rebuilds the boundary area is what the neighbours hold as ghosts (reach 0):
    // the refresh sends it in place.
    const bool refresh = options_.search.verlet && !rebuild_next_;
    refresh ? domain_->set_refresh_reach() : domain_->set_reach(displacement_since_sort_);
    const int count = int(subdomains_.size());
    for (int d = 0; d < count; ++d) {
        const auto cells = domain_->update_order(d);
        {
            ScopedPhase ph(clock(d), Phase::integrate, step, d);
            for (int edge : {0, 1}) subdomains_[d]->advance_cells(rule, cells[edge].begin, cells[edge].end);
        }
        domain_->boundary_ready(subdomains_, d);
        ScopedPhase ph(clock(d), Phase::integrate, step, d);
        subdomains_[d]->advance_cells(rule, cells[2].begin, cells[2].end);
    }
    ScopedPhase ph(host_clock_, Phase::exchange, step, 0);
    if (refresh) {
        // Counted with this step's record (a whole exchange is counted where it settles,
        // which may be this step's start).
        const ExchangeCounters c = domain_->begin_refresh(subdomains_);
        record_.exchange.ghosts_sent += c.ghosts_sent;
        record_.exchange.bytes += c.bytes;
    } else {
        domain_->begin_exchange(subdomains_);
    }
    domain_->finish_exchange(subdomains_);
}

// Each subdomain's update time of the last step, in subdomain order (the balancer's input).
std::vector<double> Simulation::last_update_times() const {
    std::vector<double> times;
    for (const PhaseTimes& t : record_.subdomain_ms) times.push_back(update_time(t));
    return times;
}

// What the balancer counts its chances by (every:K acts on multiples of K): the step, where
// every step may repartition; with lists, the rebuild the move will take effect at (the count
// of builds so far, plus one), so that the overlapped path, which decides a step before that
// rebuild, and the other, which decides at it, act alike.
long Simulation::repartition_number(long step) const {
    return options_.search.verlet ? list_builds_ + 1 : step;
}

// Every subdomain's statistics merged in subdomain order, as one process would (the kinetic
// energy is a floating-point sum, so the order is part of the result).
StepStats Simulation::gather_stats(const std::vector<StepStats>& local) const {
    StepStats merged;
    for (const StepStats& s : allgather_values(domain_->ranks(), local)) merged = merge_stats(merged, s);
    return merged;
}

// The step's wall time per compute phase is the slowest subdomain's (paper: real wall time);
// every subdomain's times and particle counts, on every rank (the balancer reads them).
void Simulation::gather_record(const std::vector<PhaseTimes>& local_ms, const std::vector<std::size_t>& local_particles) {
    record_.subdomain_ms = allgather_values(domain_->ranks(), local_ms);
    record_.subdomain_particles = allgather_values(domain_->ranks(), local_particles);
    record_.phase_ms.fill(0);
    for (const PhaseTimes& t : record_.subdomain_ms)
        for (std::size_t p = 0; p < phase_count; ++p) record_.phase_ms[p] = std::max(record_.phase_ms[p], t[p]);
}

real Simulation::verlet_skin() const { return real(options_.search.skin * scene_.params.support); }

// The lists hold while no two particles can have closed the skin: each has moved at most
// sum of dt |v| since the build, bounded from the step statistics (no per-particle state;
// the half-skin threshold leaves room for the statistics being one step newer than the move).
bool Simulation::verlet_list_expired(double dt, const StepStats& stats) {
    const SearchOptions& s = options_.search;
    if (s.rebuild_every > 0) return steps_since_build_ >= s.rebuild_every;
    const double vmax = std::sqrt(double(stats.max_speed2));
    const double amax = std::sqrt(double(stats.max_accel2));
    moved_since_build_ += dt * (vmax + 0.5 * dt * amax);
    return moved_since_build_ > 0.5 * verlet_skin();
}

WorkCounters Simulation::count_work() {
    std::vector<WorkCounters> local;
    for (auto& d : subdomains_) local.push_back(d->count_work());
    WorkCounters total;
    for (const WorkCounters& w : allgather_values(domain_->ranks(), local)) {
        total.candidates += w.candidates;
        total.neighbours += w.neighbours;
        total.ranges += w.ranges;
    }
    return total;
}

void Simulation::check_gauges(const std::vector<Gauge>& gauges) const {
    for (const Gauge& g : gauges) check_gauge(g, scene_);
}

std::vector<double> Simulation::measure_gauges(const std::vector<Gauge>& gauges) {
    std::vector<GaugeProbe> probes;
    std::vector<std::size_t> first;  // each gauge's first probe
    for (const Gauge& g : gauges) {
        first.push_back(probes.size());
        for (const GaugeProbe& p : gauge_probes(g, scene_, grid_)) probes.push_back(p);
    }
    if (probes.empty()) return {};
    std::vector<GaugeSum> local;  // subdomain after subdomain, each all its probes
    for (auto& d : subdomains_)
        for (const GaugeSum& s : d->gauge_sums(probes)) local.push_back(s);
    const std::vector<GaugeSum> all = allgather_values(domain_->ranks(), local);
    std::vector<GaugeSum> total;
    for (const GaugeProbe& p : probes) total.push_back(empty_gauge_sum(p.kind));
    for (std::size_t k = 0; k < all.size(); ++k) {
        const std::size_t q = k % probes.size();
        total[q] = merge_gauge_sums(probes[q].kind, total[q], all[k]);
    }
    std::vector<double> values;
    for (std::size_t g = 0; g < gauges.size(); ++g)
        for (double v : gauge_values(gauges[g], scene_, grid_, total.data() + first[g])) values.push_back(v);
    return values;
}

std::string Simulation::device_name() const {
    const std::string first = subdomains_.front()->device_name();
    for (const auto& d : subdomains_)
        if (d->device_name() != first) {
            std::string all;
            for (const auto& e : subdomains_) all += (all.empty() ? "" : "; ") + e->device_name();
            return all;
        }
    if (domain_->ranks().size() > 1)
        return std::to_string(subdomain_count()) + " subdomains on " + std::to_string(domain_->ranks().size()) +
               " MPI ranks, on " + first;
    return subdomains_.size() == 1 ? first : std::to_string(subdomains_.size()) + " subdomains on " + first;
}

std::size_t Simulation::neighbour_list_bytes() const {
    std::vector<std::size_t> local;
    for (const auto& d : subdomains_) local.push_back(d->neighbour_list_bytes());
    std::size_t b = 0;
    for (std::size_t x : allgather_values(domain_->ranks(), local)) b += x;
    return b;
}

std::size_t Simulation::bytes_allocated() const {
    std::vector<std::size_t> local;
    for (const auto& d : subdomains_) local.push_back(d->bytes_allocated());
    std::size_t b = 0;
    for (std::size_t x : allgather_values(domain_->ranks(), local)) b += x;
    return b;
}

SnapshotData Simulation::to_snapshot(const std::vector<ParticleArrays>& parts) const {
    SnapshotData s;
    s.time = record_.time;
    s.step = record_.step;
    const double cs[3] = {grid_.view.cell_size.x, grid_.view.cell_size.y, grid_.view.cell_size.z};
    for (const ParticleArrays& a : parts)
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (is_ghost_id(a.id[i])) continue;  // a copy; its owner writes it
            const bool out = a.cell[i] >= grid_.view.out_of_domain();
            const int3v c = out ? int3v{0, 0, 0} : grid_.view.decode(a.cell[i]);
            const int cc[3] = {c.x, c.y, c.z};
            const real off[3] = {a.pos[i].x, a.pos[i].y, a.pos[i].z};
            for (int k = 0; k < 3; ++k)
                s.position.push_back(out ? std::nan("") : grid_.origin[k] + cc[k] * cs[k] + double(off[k]));
            s.velocity.push_back(float(a.velrho[i].x));
            s.velocity.push_back(float(a.velrho[i].y));
            s.velocity.push_back(float(a.velrho[i].z));
            const real rho = density(a.velrho[i]);
            s.density.push_back(float(rho));
            s.pressure.push_back(float(tait_pressure(scene_.params, rho)));
            s.type.push_back(is_boundary(a.velrho[i]) ? 1 : 0);
            s.id.push_back(a.id[i]);
        }
    return s;
}

// Every rank's particles, in subdomain order (so the same arrays as one process).
SnapshotData Simulation::snapshot() {
    std::vector<ParticleArrays> parts;
    for (auto& d : subdomains_) parts.push_back(d->download());
    RankGroup& ranks = domain_->ranks();
    if (ranks.size() == 1) return to_snapshot(parts);
    ParticleArrays mine;
    for (const ParticleArrays& p : parts) {
        mine.pos.insert(mine.pos.end(), p.pos.begin(), p.pos.end());
        mine.velrho.insert(mine.velrho.end(), p.velrho.begin(), p.velrho.end());
        mine.cell.insert(mine.cell.end(), p.cell.begin(), p.cell.end());
        mine.id.insert(mine.id.end(), p.id.begin(), p.id.end());
    }
    ParticleArrays all;
    all.pos = allgather_values(ranks, mine.pos);
    all.velrho = allgather_values(ranks, mine.velrho);
    all.cell = allgather_values(ranks, mine.cell);
    all.id = allgather_values(ranks, mine.id);
    return to_snapshot({all});
}

}  // namespace sph
