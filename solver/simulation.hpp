#pragma once
// The time loop over a set of subdomains (one for now): kick-drift, sort, forces,
// diagnostics, kick; with per-phase timing, NVTX ranges and the blow-up check.
#include <memory>
#include <vector>

#include "backend/subdomain.hpp"
#include "core/error.hpp"
#include "io/snapshot_writer.hpp"
#include "neighbours/grid.hpp"
#include "scenes/scene.hpp"

namespace sph {

struct SolverOptions {
    BackendKind backend = BackendKind::host;
    int device = 0;
    SearchOptions search;
    double cfl = 0;       // 0: the scene's
    double fixed_dt = 0;  // > 0: a fixed step (benchmarks), no CFL
    bool diffusion = true;  // false compiles the delta-SPH term out
    double max_speed_factor = 1.0;  // a fluid speed above this times c0 is a blow-up
};

struct StepRecord {
    long step = 0;      // 1-based number of the step just taken
    double time = 0;    // simulated time after it
    double dt = 0;
    StepStats stats;
    PhaseTimes phase_ms{};
    std::size_t out_of_domain = 0;
};

// Thrown when the state blows up; last_good holds the state before the failing kick.
struct BlowUpError : RunError {
    BlowUpError(const std::string& what, SnapshotData state) : RunError(what), last_good(std::move(state)) {}
    SnapshotData last_good;
};

class Simulation {
public:
    Simulation(const Scene& scene, const SolverOptions& options);

    const StepRecord& step();
    SnapshotData snapshot();  // absolute positions, for HDF5
    WorkCounters count_work();

    const Scene& scene() const { return scene_; }
    const Grid& grid() const { return grid_; }
    long steps_taken() const { return record_.step; }
    double time() const { return record_.time; }
    std::string device_name() const { return subdomains_.front()->device_name(); }
    std::size_t bytes_allocated() const;
    std::size_t particle_count() const { return n_total_; }
    long neighbour_list_builds() const { return list_builds_; }
    std::size_t neighbour_list_bytes() const;
    std::size_t fluid_count() const { return n_fluid_; }

private:
    double next_dt() const;
    real verlet_skin() const;
    bool verlet_list_expired(double dt);
    SnapshotData to_snapshot(const ParticleArrays& a) const;

    Scene scene_;  // keeps params and metadata; positions are released after upload
    SolverOptions options_;
    Grid grid_;
    std::vector<std::unique_ptr<Subdomain>> subdomains_;
    StatsLimits limits_;
    StepRecord record_;
    std::size_t n_total_ = 0, n_fluid_ = 0;
    long steps_since_build_ = 0, list_builds_ = 0;
    double moved_since_build_ = 0;
};

// Converts absolute positions to the cell-relative form of particle.hpp.
ParticleArrays make_particle_arrays(const Scene& scene, const Grid& grid);

}  // namespace sph
