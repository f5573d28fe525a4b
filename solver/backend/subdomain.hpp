#pragma once
// A subdomain is the unit of execution: one device's share of space, its particles and the
// phases of a step run on them. The host backend (OpenMP) and the CUDA backend implement
// the same interface, so the time loop, tests and harness never know which one runs.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backend/implementation_variants.hpp"
#include "backend/phase.hpp"
#include "core/params.hpp"
#include "core/smoothing_kernels.hpp"
#include "neighbours/cell_search.hpp"
#include "neighbours/grid.hpp"
#include "physics/gauges.hpp"
#include "physics/integration.hpp"
#include "physics/interaction.hpp"
#include "physics/step_stats.hpp"

namespace sph {

// The particle arrays as the host sees them (same encoding as on the device, see particle.hpp).
// velrho_prev is the previous step's velocity and density, which the Verlet scheme steps
// from (physics/integration.hpp); upload() takes velrho when it is empty.
struct ParticleArrays {
    std::vector<real4> pos, velrho, velrho_prev, force;
    std::vector<std::uint32_t> cell, id;
    std::size_t size() const { return id.size(); }
};

// Particle arrays an exchange carries, in a subdomain's own memory: device memory of GPU
// `device` (whose work is queued on `stream`, a cudaStream_t), or host memory (device -1).
struct ParticleSpan {
    real4* pos = nullptr;
    real4* velrho = nullptr;
    real4* velrho_prev = nullptr;
    std::uint32_t* cell = nullptr;
    std::uint32_t* id = nullptr;
    std::size_t count = 0;
    int device = -1;
    void* stream = nullptr;
};

// What accept_received_in kept of a receive area.
struct ReceivedCount {
    std::size_t kept = 0, owned = 0;
};

struct SubdomainConfig {
    PhysicsParams params;
    GridView grid;
    KernelType kernel = KernelType::wendland;
    bool diffusion = true;
    SearchOptions search;
    bool integrate_boundary = false;  // true only to measure what skipping it saves (skip_bench)
    ImplementationVariants variants{};  // how the CUDA drivers run the phases (implementation_variants.hpp)
    // Every particle of the run, which bounds what any one subdomain holds (each particle at
    // most once): layouts that must agree between subdomains are decided from it, not from
    // each subdomain's count (the CUDA lists' entries, which ghost refreshes copy between).
    std::size_t particles_in_run = 0;
};

struct WorkCounters {
    unsigned long long candidates = 0, neighbours = 0, ranges = 0;
};

enum class BackendKind { host, cuda };

class Subdomain {
public:
    virtual ~Subdomain() = default;
    virtual BackendKind backend() const = 0;
    virtual std::string device_name() const = 0;
    // Where its memory lives and its work is queued, for the transports: the GPU index (-1:
    // host memory) and the cudaStream_t (nullptr on the host).
    virtual int device() const = 0;
    virtual void* stream() const = 0;

    virtual void upload(const ParticleArrays& particles) = 0;
    virtual ParticleArrays download() = 0;

    // Phase neighbour_list: sort by (cell, id) and build the cell ranges.
    virtual void sort_by_cell() = 0;
    // Phase forces: acceleration and density rate of every particle in the domain.
    virtual void compute_forces() = 0;
    // Verlet lists: after a sort, store every neighbour within support + skin (the grid's
    // cells must reach that far; RunError otherwise); the listed force loop then reuses the
    // lists (no sort) until the Simulation decides to rebuild.
    virtual void build_neighbour_list(real skin) = 0;
    virtual void compute_forces_listed() = 0;
    virtual std::size_t neighbour_list_bytes() const = 0;
    // The stored lists, entry by entry as the build left them (ListEntry codes decoded to
    // particle indices): particle i's entries are index[first[i], first[i + 1]), i in the
    // sorted order. For the tests that hold one build's lists to another's.
    struct StoredLists {
        std::vector<std::uint32_t> first, index;
    };
    virtual StoredLists download_neighbour_lists() = 0;
    // Phase integrate: one step of the owned particles from the forces just computed; it
    // also refreshes P / rho^2, so advance(euler_step(0)) primes a freshly uploaded state.
    virtual void advance(const TimeStep& step) = 0;
    // The same update for the owned particles of the cells [first_cell, end_cell) only (as
    // the last sort placed them): a decomposition updates the cells near its slab edges
    // first and sends them while the rest is updated (paper section 5.3). Ranges that
    // together cover the owned cells once give bitwise what advance(step) gives.
    virtual void advance_cells(const TimeStep& step, std::uint32_t first_cell, std::uint32_t end_cell) = 0;
    // Phase diagnostics: reductions over the state advance(step) will produce.
    virtual StepStats reduce_stats(const TimeStep& step, const StatsLimits& limits) = 0;
    // Not timed: counts the neighbour search's work for the current sorted state.
    virtual WorkCounters count_work() = 0;
    // Not timed: each probe's partial sums over the particles this subdomain owns, in the
    // state the last advance left (physics/gauges.hpp); deterministic (fixed summation order).
    virtual std::vector<GaugeSum> gauge_sums(const std::vector<GaugeProbe>& probes) = 0;

    // The port a decomposition (multi/) works through, in cells only: after a sort, the
    // particles of a cell range are one contiguous range. Per-particle phases (update, forces, statistics) act on the particles of the owned cells;
    // the rest are ghosts of neighbours or particles that left the domain. Setting the owned
    // cells also marks every particle of another in-domain cell as a ghost (ghost_id_flag).
    virtual void set_owned_cells(std::uint32_t begin, std::uint32_t end) = 0;
    // Drops every particle outside [begin, end) except those that left the domain. The cell
    // ranges of the last sort are kept valid for what is left (cells outside [begin, end)
    // become empty), so the per-slice counts, the owned range and set_owned_cells still hold.
    virtual void keep_only_cells(std::uint32_t begin, std::uint32_t end) = 0;
    // cell_start at the given cells (counts per slice are differences of these).
    virtual std::vector<std::uint32_t> cell_starts(const std::vector<std::uint32_t>& cells) = 0;
    virtual std::size_t size() const = 0;  // particles held, ghosts included

    // What transports read and write: sorted particles
    // [first, first + count) in place, and a receive area that accept_received() appends.
    virtual ParticleSpan particles(std::size_t first, std::size_t count) = 0;
    // The same particles' state as the listed forces read it of a neighbour: pos, velrho,
    // velrho_prev and cell, with id null (a ghost refreshed from it keeps its ghost flag).
    // A backend whose lists read another position array (CUDA's list frame) returns that; its
    // ghosts' pos then stays the rebuild's while their cell follows the owner, so nothing but
    // the listed forces may read a ghost's pos between rebuilds (the gauges read owned fluid
    // only, and a body's force its owned particles).
    virtual ParticleSpan state(std::size_t first, std::size_t count) {
        ParticleSpan s = particles(first, count);
        s.id = nullptr;
        return s;
    }
    // After a refresh wrote state() into ghosts [first, first + count) (ordered after the
    // copies): what the listed forces read of them and state() does not carry is brought up
    // to date (CUDA's cell coordinates of plain list entries, from the cells received).
    virtual void ghosts_refreshed(std::size_t first, std::size_t count) {
        (void)first;
        (void)count;
    }
    virtual ParticleSpan receive_area(std::size_t count) = 0;
    virtual void accept_received() = 0;  // unsorted until the next sort
    // Appends only the received particles whose cell lies in [begin, end) (the rest, sent
    // whole with the boundary slices they were in, are not needed here, or left the domain);
    // returns how many were kept and how many of those lie in [owned_begin, owned_end).
    virtual ReceivedCount accept_received_in(std::uint32_t begin, std::uint32_t end, std::uint32_t owned_begin,
                                             std::uint32_t owned_end) = 0;
    virtual void synchronize() = 0;      // waits for the work queued on this subdomain

    // Owned particles inside the domain after the last sort.
    virtual std::size_t active_count() const = 0;
    virtual std::size_t bytes_allocated() const = 0;
    virtual PhaseClock& clock() = 0;
};

// Throws RunError when the grid's cells are too small for lists of this reach.
void require_stencil_reach(const SubdomainConfig& cfg, real reach);

std::unique_ptr<Subdomain> make_host_subdomain(const SubdomainConfig& cfg, std::size_t capacity);
// Throws RunError naming the need and the free memory when the scene does not fit.
std::unique_ptr<Subdomain> make_cuda_subdomain(const SubdomainConfig& cfg, std::size_t capacity, int device);
bool cuda_backend_available();  // compiled in and a GPU present
int cuda_device_count();        // 0 without CUDA
std::string cuda_device_summary();  // names, driver and runtime versions; "" without CUDA

}  // namespace sph
