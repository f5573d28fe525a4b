// The host backend: the same per-particle functions as the CUDA kernels, run by OpenMP loops.
// CI has no GPU, so this is how every algorithm is tested.
#include <algorithm>
#include <numeric>
#include <string>

#include "backend/key_order.hpp"
#include "backend/steady_phase_clock.hpp"
#include "backend/subdomain.hpp"
#include "core/error.hpp"
#include "physics/dispatch.hpp"
#include "physics/integration.hpp"

namespace sph {
namespace {

class HostSubdomain final : public Subdomain {
public:
    explicit HostSubdomain(const SubdomainConfig& cfg) : cfg_(cfg), cell_start_(cfg.grid.cell_count() + 1, 0) {}

    BackendKind backend() const override { return BackendKind::host; }
    std::string device_name() const override { return "host"; }
    int device() const override { return -1; }
    void* stream() const override { return nullptr; }

    void upload(const ParticleArrays& p) override {
        a_ = p;
        if (a_.velrho_prev.empty()) a_.velrho_prev = a_.velrho;
        a_.force.assign(p.size(), real4{0, 0, 0, 0});
        if (!p.force.empty()) a_.force = p.force;
        owned_lo_ = 0;
        owned_hi_ = p.size();
    }
    ParticleArrays download() override { return a_; }

    void set_owned_cells(std::uint32_t begin, std::uint32_t end) override {
        owned_cells_[0] = begin;
        owned_cells_[1] = end;
        update_owned_range();
        const std::uint32_t outside = cfg_.grid.out_of_domain();
        const std::ptrdiff_t n = std::ptrdiff_t(a_.size());
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = 0; i < n; ++i)
            a_.id[i] = mark_ghost(a_.id[i], a_.cell[i], begin, end, outside);
    }
    void keep_only_cells(std::uint32_t begin, std::uint32_t end) override {
        const std::uint32_t ncells = cfg_.grid.cell_count();
        const std::size_t lo = cell_start_[begin], hi = cell_start_[end];
        const std::size_t out_lo = cell_start_[ncells], n = a_.size();
        if (lo == 0 && hi == out_lo) return;  // nothing to drop
        auto keep = [&](auto& v) {
            using V = std::decay_t<decltype(v)>;
            V kept(v.begin() + lo, v.begin() + hi);
            kept.insert(kept.end(), v.begin() + out_lo, v.begin() + n);
            v.swap(kept);
        };
        keep(a_.pos);
        keep(a_.velrho);
        keep(a_.velrho_prev);
        keep(a_.cell);
        keep(a_.id);
        a_.force.resize(a_.size());  // forces are recomputed before they are read
        // What was kept is where it was, shifted down by lo; cells outside become empty.
        for (std::uint32_t c = 0; c <= ncells; ++c)
            cell_start_[c] = std::uint32_t(std::clamp<std::size_t>(cell_start_[c], lo, hi) - lo);
        update_owned_range();
    }
    ParticleSpan particles(std::size_t first, std::size_t count) override {
        return {a_.pos.data() + first, a_.velrho.data() + first, a_.velrho_prev.data() + first,
                a_.cell.data() + first, a_.id.data() + first, count};
    }
    ParticleSpan receive_area(std::size_t count) override {
        for (auto* v : {&received_.pos, &received_.velrho, &received_.velrho_prev}) v->resize(count);
        for (auto* v : {&received_.cell, &received_.id}) v->resize(count);
        return {received_.pos.data(), received_.velrho.data(), received_.velrho_prev.data(), received_.cell.data(),
                received_.id.data(), count};
    }
    void accept_received() override {
        a_.pos.insert(a_.pos.end(), received_.pos.begin(), received_.pos.end());
        a_.velrho.insert(a_.velrho.end(), received_.velrho.begin(), received_.velrho.end());
        a_.velrho_prev.insert(a_.velrho_prev.end(), received_.velrho_prev.begin(), received_.velrho_prev.end());
        a_.cell.insert(a_.cell.end(), received_.cell.begin(), received_.cell.end());
        a_.id.insert(a_.id.end(), received_.id.begin(), received_.id.end());
        a_.force.resize(a_.size());
        received_ = {};
    }
    ReceivedCount accept_received_in(std::uint32_t begin, std::uint32_t end, std::uint32_t owned_begin,
                                     std::uint32_t owned_end) override {
        ReceivedCount count;
        for (std::size_t i = 0; i < received_.size(); ++i) {
            const std::uint32_t c = received_.cell[i];
            if (c < begin || c >= end) continue;
            a_.pos.push_back(received_.pos[i]);
            a_.velrho.push_back(received_.velrho[i]);
            a_.velrho_prev.push_back(received_.velrho_prev[i]);
            a_.cell.push_back(c);
            a_.id.push_back(received_.id[i]);
            ++count.kept;
            count.owned += c >= owned_begin && c < owned_end;
        }
        a_.force.resize(a_.size());
        received_ = {};
        return count;
    }
    void synchronize() override {}
    std::vector<std::uint32_t> cell_starts(const std::vector<std::uint32_t>& cells) override {
        std::vector<std::uint32_t> out;
        for (std::uint32_t c : cells) out.push_back(cell_start_[c]);
        return out;
    }
    std::size_t size() const override { return a_.size(); }

    void sort_by_cell() override {
        const std::size_t n = a_.size();
        order_.resize(n);
        keys_.resize(n);
#pragma omp parallel for
        for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i)
            keys_[i] = (std::uint64_t(a_.cell[i]) << 32) | a_.id[i];
        std::iota(order_.begin(), order_.end(), 0u);
        order_by_keys(keys_, order_);
        gather(a_.pos);
        gather(a_.velrho);
        gather(a_.velrho_prev);
        gather(a_.cell);
        gather(a_.id);
        // cell_start[c] = first sorted particle with cell >= c.
        const std::uint32_t ncells = cfg_.grid.cell_count();
        std::uint32_t j = 0;
        for (std::uint32_t c = 0; c <= ncells; ++c) {
            while (j < n && a_.cell[j] < c) ++j;
            cell_start_[c] = j;
        }
        update_owned_range();
    }

    void compute_forces() override {
        const ForceInputs in = inputs();
        const PhysicsParams p = cfg_.params;
        real4* force = a_.force.data();
        const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
        if (p.shift > 0) concentration_gradient_loop(in);
        dispatch_physics(cfg_.kernel, cfg_.diffusion, cfg_.search, [&](auto k, auto s, auto diffusion) {
            using Kernel = typename decltype(k)::type;
            using Search = typename decltype(s)::type;
            const Kernel kernel(p.h);
#pragma omp parallel for schedule(static)
            for (std::ptrdiff_t i = lo; i < n; ++i)
                force[i] = particle_force<Kernel, Search, decltype(diffusion)::value>(std::uint32_t(i), in, p, kernel);
        });
    }

    void build_neighbour_list(real skin) override {
        const ForceInputs in = inputs();
        const real reach = cfg_.params.support + skin;
        require_stencil_reach(cfg_, reach);
        const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
        list_count_.assign(a_.size(), 0);
        std::uint32_t longest = 0;
        for (int attempt = 0; attempt < 2; ++attempt) {
            list_index_.resize(std::size_t(list_capacity_) * a_.size());
            dispatch_search(cfg_.search, [&](auto s) {
                using Search = typename decltype(s)::type;
#pragma omp parallel for reduction(max : longest)
                for (std::ptrdiff_t i = lo; i < n; ++i) {
                    const std::uint32_t c = build_particle_list<Search>(std::uint32_t(i), in, reach * reach,
                                                                        list_index_.data(), std::uint32_t(a_.size()),
                                                                        list_capacity_);
                    list_count_[i] = c;
                    longest = std::max(longest, c);
                }
            });
            if (longest <= list_capacity_) return;
            list_capacity_ = list_capacity(longest + longest / 5 + 8);  // grow with room, then build again
        }
    }

    void compute_forces_listed() override {
        const ForceInputs in = inputs();
        const NeighbourList list{list_index_.data(), list_count_.data(), std::uint32_t(a_.size())};
        const PhysicsParams p = cfg_.params;
        real4* force = a_.force.data();
        const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
        dispatch_kernel(cfg_.kernel, cfg_.diffusion, [&](auto k, auto diffusion) {
            using Kernel = typename decltype(k)::type;
            const Kernel kernel(p.h);
#pragma omp parallel for schedule(static)
            for (std::ptrdiff_t i = lo; i < n; ++i)
                force[i] = a_.cell[i] < cfg_.grid.out_of_domain()
                               ? particle_force_listed<Kernel, decltype(diffusion)::value>(std::uint32_t(i), in, list, p,
                                                                                          kernel)
                               : real4{0, 0, 0, 0};
        });
    }

    std::size_t neighbour_list_bytes() const override {
        return (list_index_.size() + list_count_.size()) * sizeof(std::uint32_t);
    }
    StoredLists download_neighbour_lists() override {
        StoredLists out{{0}, {}};
        for (std::size_t i = 0; i < list_count_.size(); ++i) {
            for (std::uint32_t k = 0; k < list_count_[i]; ++k)
                out.index.push_back(list_index_[list_slot(k, std::uint32_t(i), std::uint32_t(a_.size()))]);
            out.first.push_back(std::uint32_t(out.index.size()));
        }
        return out;
    }

    void advance(const TimeStep& step) override { advance_range(step, owned_lo_, owned_hi_); }
    void advance_cells(const TimeStep& step, std::uint32_t first_cell, std::uint32_t end_cell) override {
        const std::uint32_t ncells = cfg_.grid.cell_count();
        const std::size_t lo = std::max<std::size_t>(owned_lo_, cell_start_[std::min(first_cell, ncells)]);
        const std::size_t hi = std::min<std::size_t>(owned_hi_, cell_start_[std::min(end_cell, ncells)]);
        if (hi > lo) advance_range(step, lo, hi);
    }

    StepStats reduce_stats(const TimeStep& step, const StatsLimits& limits) override {
        StepStats total;
        const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
#pragma omp parallel
        {
            StepStats local;
#pragma omp for schedule(static) nowait
            for (std::ptrdiff_t i = lo; i < n; ++i)
                local = merge_stats(local, particle_stats(std::uint32_t(i), a_.velrho.data(), a_.velrho_prev.data(),
                                                          a_.force.data(), a_.id.data(), step, cfg_.params, limits));
#pragma omp critical
            total = merge_stats(total, local);
        }
        return total;
    }

    WorkCounters count_work() override {
        const ForceInputs in = inputs();
        unsigned long long cand = 0, nb = 0, ranges = 0;
        const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
        dispatch_search(cfg_.search, [&](auto s) {
            using Search = typename decltype(s)::type;
#pragma omp parallel for reduction(+ : cand, nb, ranges)
            for (std::ptrdiff_t i = lo; i < n; ++i) {
                const SearchWork w = particle_search_work<Search>(std::uint32_t(i), in, cfg_.params);
                cand += w.candidates;
                nb += w.neighbours;
                ranges += w.ranges;
            }
        });
        return {cand, nb, ranges};
    }

    std::vector<GaugeSum> gauge_sums(const std::vector<GaugeProbe>& probes) override {
        const std::uint32_t ncells = cfg_.grid.cell_count();
        const GaugeInputs in{inputs(), a_.id.data(), std::min(owned_cells_[0], ncells), std::min(owned_cells_[1], ncells)};
        const PhysicsParams p = cfg_.params;
        std::vector<GaugeSum> out;
        dispatch_kernel(cfg_.kernel, false, [&](auto k, auto) {
            using Kernel = typename decltype(k)::type;
            const Kernel kernel(p.h);
            for (const GaugeProbe& probe : probes) {
                GaugeSum total = empty_gauge_sum(probe.kind);
                if (probe.kind == GaugeKind::force) {
                    // Per particle in parallel, then summed in particle order.
                    const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
                    std::vector<real3> per(std::size_t(n - lo));
#pragma omp parallel for schedule(static)
                    for (std::ptrdiff_t i = lo; i < n; ++i)
                        per[std::size_t(i - lo)] = fluid_force_on_body(std::uint32_t(i), probe, in, p, kernel);
                    for (const real3& f : per) {
                        total.v[0] += double(f.x);
                        total.v[1] += double(f.y);
                        total.v[2] += double(f.z);
                    }
                } else {
                    const GaugeStencil st = probe_stencil(probe, cfg_.grid, p);
                    for (std::uint32_t c = 0; c < st.cells(); ++c)
                        total = merge_gauge_sums(probe.kind, total,
                                                 probe_cell_sum(probe, in, p, kernel, st.cell(cfg_.grid, c)));
                }
                out.push_back(total);
            }
        });
        return out;
    }

    std::size_t active_count() const override { return owned_hi_ - owned_lo_; }
    std::size_t bytes_allocated() const override {
        return a_.size() * (4 * sizeof(real4) + 2 * sizeof(std::uint32_t) + 12) +
               cell_start_.size() * sizeof(std::uint32_t) + neighbour_list_bytes();
    }
    PhaseClock& clock() override { return clock_; }

private:
    void advance_range(const TimeStep& step, std::size_t first, std::size_t end) {
        cfg_.integrate_boundary ? advance_loop<true>(step, first, end) : advance_loop<false>(step, first, end);
    }
    template <bool IntegrateBoundary>
    void advance_loop(const TimeStep& step, std::size_t first, std::size_t end) {
        const std::ptrdiff_t lo = std::ptrdiff_t(first), n = std::ptrdiff_t(end);
#pragma omp parallel for schedule(static)
        for (std::ptrdiff_t i = lo; i < n; ++i)
            particle_advance<IntegrateBoundary>(std::uint32_t(i), a_.pos.data(), a_.velrho.data(), a_.velrho_prev.data(),
                                                a_.cell.data(), KeptCells{}, a_.force.data(), gradient(), step, cfg_.grid,
                                                cfg_.params);
    }
    void update_owned_range() {
        const std::uint32_t ncells = cfg_.grid.cell_count();
        owned_lo_ = cell_start_[std::min(owned_cells_[0], ncells)];
        owned_hi_ = cell_start_[std::min(owned_cells_[1], ncells)];
    }
    ForceInputs inputs() const {
        return {a_.pos.data(), a_.velrho.data(), a_.velrho_prev.data(), a_.cell.data(), cell_start_.data(), nullptr,
                cfg_.grid, nullptr};
    }
    // Shifting only (the Simulation refuses it with Verlet lists, whose cells go stale).
    void concentration_gradient_loop(const ForceInputs& in) {
        grad_c_.resize(a_.size());
        const PhysicsParams p = cfg_.params;
        const std::ptrdiff_t lo = std::ptrdiff_t(owned_lo_), n = std::ptrdiff_t(owned_hi_);
        dispatch_physics(cfg_.kernel, false, cfg_.search, [&](auto k, auto s, auto) {
            using Kernel = typename decltype(k)::type;
            using Search = typename decltype(s)::type;
            const Kernel kernel(p.h);
#pragma omp parallel for schedule(static)
            for (std::ptrdiff_t i = lo; i < n; ++i)
                grad_c_[i] = particle_concentration_gradient<Kernel, Search>(std::uint32_t(i), in, p, kernel);
        });
    }
    const real4* gradient() const {
        return cfg_.params.shift > 0 && grad_c_.size() >= a_.size() ? grad_c_.data() : nullptr;
    }
    template <class T>
    void gather(std::vector<T>& v) {
        scratch_.resize(v.size() * sizeof(T));
        T* tmp = reinterpret_cast<T*>(scratch_.data());
        const std::ptrdiff_t n = std::ptrdiff_t(v.size());
#pragma omp parallel for
        for (std::ptrdiff_t i = 0; i < n; ++i) tmp[i] = v[order_[i]];
        std::copy(tmp, tmp + n, v.begin());
    }

    SubdomainConfig cfg_;
    ParticleArrays a_, received_;
    std::vector<std::uint32_t> cell_start_, order_, list_index_, list_count_;
    std::vector<real4> grad_c_;  // shifting only: per particle, from compute_forces' gradient pass
    std::uint32_t list_capacity_ = 64;
    std::vector<std::uint64_t> keys_;
    std::vector<unsigned char> scratch_;
    std::size_t owned_lo_ = 0, owned_hi_ = 0;
    std::uint32_t owned_cells_[2] = {0, 0xffffffffu};
    SteadyPhaseClock clock_;
};

}  // namespace

void require_stencil_reach(const SubdomainConfig& cfg, real reach) {
    if (stencil_reaches(cfg.grid, cfg.search.cells_per_support, reach)) return;
    const real3 cs = cfg.grid.cell_size;
    throw RunError("Verlet lists of reach " + std::to_string(reach) + " m (support + skin) need cells of at least " +
                   std::to_string(reach / cfg.search.cells_per_support) + " m, but the grid's are " +
                   std::to_string(std::min({cs.x, cs.y, cs.z})) + " m: pairs beyond the stencil would be missed");
}

std::unique_ptr<Subdomain> make_host_subdomain(const SubdomainConfig& cfg, std::size_t) {
    return std::make_unique<HostSubdomain>(cfg);
}

}  // namespace sph
