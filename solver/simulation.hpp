#pragma once
// The time loop over a set of subdomains: (drop ghosts), (balance), sort, (exchange), forces,
// diagnostics, advance (the Verlet update); with per-phase timing, NVTX ranges and the
// blow-up check. With several subdomains and SolverOptions::overlap (paper section 5.3):
// (settle the last step's exchange: drop ghosts, sort), forces, (balance, on the host under
// the forces), diagnostics, advance the boundary slices, advance the inner slices while the
// boundary slices travel. With Verlet lists (SearchOptions::verlet; several subdomains: on
// the host without overlap so far) only a rebuild step drops, balances, sorts and exchanges,
// and builds the lists after the exchange; the steps between refresh the ghosts in place.
// One subdomain is a plain single-device run; N subdomains split space into X slabs
// (paper section 5), on N GPUs, on one GPU, or on the host, in one process or spread over the
// ranks of an MPI job (multi/rank_group.hpp). The slabs' per-step life is the SlabDomain's;
// this loop calls it the same way for one subdomain or many. Under MPI every rank runs this
// loop on its own subdomains, and the records (statistics, per-subdomain times, counters)
// are gathered so that every rank holds the whole run's, merged in subdomain order.
#include <memory>
#include <string>
#include <vector>

#include "backend/steady_phase_clock.hpp"
#include "backend/subdomain.hpp"
#include "core/error.hpp"
#include "gauge.hpp"
#include "io/snapshot_writer.hpp"
#include "multi/rank_group.hpp"
#include "multi/slab_domain.hpp"
#include "neighbours/grid.hpp"
#include "scenes/scene.hpp"

namespace sph {

struct SolverOptions {
    BackendKind backend = BackendKind::host;
    int device = 0;          // GPU of a one-subdomain run
    int subdomains = 1;      // X slabs (logical devices)
    std::vector<int> device_map;  // GPU of each subdomain (among its rank's node's); empty: multi/gpu_choice.hpp
    // MPI ranks of one node may share its GPUs (more ranks than GPUs); refused otherwise.
    bool share_gpus = false;
    // Hand GPU memory to a CUDA-aware MPI: checked (refused on the host backend, in one process
    // and of an MPI without CUDA support); the particles are staged through pinned host memory
    // either way so far (multi/rank_staging.hpp).
    bool gpu_direct = false;
    std::string balancer = "none";  // none, simple, every:K, threshold, equal-time[:F]
    // The processes the subdomains are spread over (one rank holds a contiguous block of
    // them); nullptr: this process's group, process_ranks() (MPI when mpirun started it).
    RankGroup* ranks = nullptr;
    TransportKind transport = TransportKind::automatic;  // how particles travel between subdomains
    // Paper section 5.3 (several subdomains): update the boundary slices first and send them
    // whole while the inner slices are updated, the balancer deciding while the forces run;
    // false: balance, then exchange, at the start of each step, nothing overlapped. The
    // particles are bitwise the same either way.
    bool overlap = true;
    SearchOptions search;
    // How the CUDA backend runs the search's phases (fallbacks, kept selectable to test and
    // time them); the physics is the same either way.
    ImplementationVariants variants;
    double cfl = 0;       // 0: the scene's
    double fixed_dt = 0;  // > 0: a fixed step (benchmarks), no CFL
    // Every k-th step of the Verlet scheme is an Euler step (DualSPHysics's VerletSteps, 40):
    // it keeps the even and odd steps' leapfrog chains from drifting apart.
    int euler_every = 40;
    bool diffusion = true;  // false compiles the delta-SPH term out
    double max_speed_factor = 1.0;  // a fluid speed above this times c0 is a blow-up
    bool timing = true;  // false: no CUDA events (profiling passes); NVTX ranges stay
    // true: the grid covers the particles' initial bounding box grown by one support (within
    // the scene's domain) instead of the whole domain: fewer cells to sort into and scan, for
    // scenes whose walls enclose every particle; fluid leaving that box is dropped.
    bool grid_fits_particles = false;
};

struct StepRecord {
    long step = 0;      // 1-based number of the step just taken
    double time = 0;    // simulated time after it
    double dt = 0;
    StepStats stats;
    PhaseTimes phase_ms{};  // the slowest subdomain; exchange and balance: host wall time
    std::vector<PhaseTimes> subdomain_ms;  // per subdomain
    std::vector<std::size_t> subdomain_particles;  // owned particles per subdomain
    std::size_t out_of_domain = 0;
    int slices_moved = 0;
    ExchangeCounters exchange;
    // The transfers of the step's exchange alone: overlapped on the CUDA backend (peer, nccl),
    // the copies on the transport's streams (CUDA events), which run under the inner update
    // and so are not part of the phases; otherwise the host's exchange phase.
    double transfer_ms = 0;
    double wall_ms = 0;  // host wall clock of the whole step

    // The figures derived from the phase times, computed here only (the harness's tables,
    // summaries and calibration all read them from the record):
    // the whole step, the sum of its phases (the slowest subdomain's, exchange and balance added);
    double step_ms() const {
        double total = 0;
        for (double t : phase_ms) total += t;
        return total;
    }
    // the paper's real wall time of the update: the slowest subdomain's forces + integration;
    double update_ms() const {
        double worst = 0;
        for (const PhaseTimes& t : subdomain_ms) worst = worst > update_time(t) ? worst : update_time(t);
        return subdomain_ms.empty() ? update_time(phase_ms) : worst;
    }
    // the ideal update (paper Fig. 5 and 8): the mean over subdomains.
    double update_ideal_ms() const {
        if (subdomain_ms.empty()) return update_time(phase_ms);
        double sum = 0;
        for (const PhaseTimes& t : subdomain_ms) sum += update_time(t);
        return sum / double(subdomain_ms.size());
    }
};

// Thrown when the state blows up; last_good holds the state before the failing update. The
// fields repeat what the message says, for studies that tabulate failures (sphbench stability).
struct BlowUpError : RunError {
    BlowUpError(const std::string& what, SnapshotData state, long failed_step, std::uint32_t particle_id,
                std::string what_quantity)
        : RunError(what), last_good(std::move(state)), step(failed_step), particle(particle_id),
          quantity(std::move(what_quantity)) {}
    SnapshotData last_good;
    long step = 0;                // the step that failed
    std::uint32_t particle = 0;   // the particle's stable id
    std::string quantity;         // "acceleration", "speed" or "density"
};

class Simulation {
public:
    Simulation(const Scene& scene, const SolverOptions& options);

    const StepRecord& step();
    SnapshotData snapshot();  // absolute positions of owned particles, for HDF5
    WorkCounters count_work();
    // Throws InputError for a gauge that does not fit the scene (gauge.hpp), before any step.
    void check_gauges(const std::vector<Gauge>& gauges) const;
    // The gauges' column values (gauge_columns, in order) in the current state, computed by
    // the backends over the particles each subdomain owns and summed in subdomain order
    // (every rank gets them).
    std::vector<double> measure_gauges(const std::vector<Gauge>& gauges);

    const Scene& scene() const { return scene_; }
    const Grid& grid() const { return grid_; }
    long steps_taken() const { return record_.step; }
    double time() const { return record_.time; }
    std::string device_name() const;
    std::size_t bytes_allocated() const;
    std::size_t particle_count() const { return n_total_; }
    long neighbour_list_builds() const { return list_builds_; }
    std::size_t neighbour_list_bytes() const;
    std::size_t fluid_count() const { return n_fluid_; }
    int subdomain_count() const { return domain_->subdomains(); }  // on every rank
    const SlabDecomposition* decomposition() const { return domain_->split() ? &domain_->decomposition() : nullptr; }
    // The transport of a multi-subdomain run ("" for one subdomain), and why it was chosen
    // when that is worth saying (a fallback).
    std::string transport_name() const { return domain_->transport_name(); }
    const std::string& transport_note() const { return domain_->transport_note(); }
    // How particles between MPI ranks travel ("" in one process): "host-memory" or
    // "staged-pinned", and why when that is not what was asked (GPU-direct).
    std::string rank_transport_name() const { return domain_->rank_transport_name(); }
    const std::string& rank_transport_note() const { return domain_->rank_transport_note(); }
    RankGroup& ranks() const { return domain_->ranks(); }
    // Overlapping (paper 5.3): how many slices beyond the neighbours' ghosts the last update's
    // boundary slices reached (at least 1, more when particles may move further; 0 on a
    // refresh of Verlet lists' ghosts, whose boundary areas are the neighbours' ghosts).
    int overlap_reach() const { return domain_->reach(); }

private:
    double next_dt() const;
    void check_periodic_options() const;
    real verlet_skin() const;
    bool verlet_list_expired(double dt, const StepStats& stats);
    void make_subdomains(const ParticleArrays& all);
    std::vector<int> subdomain_gpus(RankGroup& ranks, const SubdomainPlacement& placement) const;
    void exchange_particles(long step);
    void refresh_ghosts(long step);
    template <class Exchange> void timed_exchange(long step, Exchange exchange);
    void settle_exchange(long step);
    void advance_overlapped(const TimeStep& rule, const StepStats& stats, long step);
    std::vector<double> last_update_times() const;
    long repartition_number(long step) const;
    StepStats gather_stats(const std::vector<StepStats>& local) const;
    void gather_record(const std::vector<PhaseTimes>& local_ms, const std::vector<std::size_t>& local_particles);
    SnapshotData to_snapshot(const std::vector<ParticleArrays>& parts) const;
    PhaseClock& clock(int d) { return options_.timing ? subdomains_[d]->clock() : untimed_; }

    Scene scene_;  // keeps params and metadata; positions are released after upload
    SolverOptions options_;
    Grid grid_;
    std::vector<std::unique_ptr<Subdomain>> subdomains_;  // this rank's
    std::unique_ptr<SlabDomain> domain_;
    SteadyPhaseClock host_clock_;
    NullPhaseClock untimed_;
    StatsLimits limits_;
    StepRecord record_;
    std::size_t n_total_ = 0, n_fluid_ = 0;
    long steps_since_build_ = 0, list_builds_ = 0;
    double moved_since_build_ = 0;
    // Decided after the diagnostics of a step, for the next one (the overlapped exchange at
    // the end of the step is a rebuild's or a refresh).
    bool rebuild_next_ = false;
    // Overlapping: how far any particle may have moved since the last sort (the boundary
    // slices are index ranges of that sort; with lists it is several steps old).
    double displacement_since_sort_ = 0;
};

// Converts absolute positions to the cell-relative form of particle.hpp.
ParticleArrays make_particle_arrays(const Scene& scene, const Grid& grid);

}  // namespace sph
