// The CUDA backend: one subdomain on one GPU, its buffers, its stream and its event clock.
// Kernels are reached only through the driver functions of cuda_drivers.cuh.
#include <cub/device/device_radix_sort.cuh>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "backend/cuda_drivers.cuh"
#include "backend/cuda_gauges.cuh"
#include "backend/cuda_phase_clock.cuh"
#include "backend/device_buffer.cuh"

namespace sph {
namespace {

// Bytes per particle of the buffers below (what the memory estimate and the report use).
constexpr std::size_t bytes_per_particle =
    3 * sizeof(real4) * 2 + sizeof(real4) + 2 * sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t) +
    2 * sizeof(std::uint32_t);

class CudaSubdomain final : public Subdomain {
public:
    CudaSubdomain(const SubdomainConfig& cfg, std::size_t capacity, int device)
        : cfg_(cfg), device_(device), stream_(create_stream(device)), clock_(stream_, device) {
        cudaDeviceProp prop{};
        SPH_CUDA_CHECK(cudaGetDeviceProperties(&prop, device));
        name_ = std::string(prop.name) + " (GPU " + std::to_string(device) + ")";
        const std::uint32_t ncells = cfg.grid.cell_count();
        std::size_t sort_temp = 0;
        cub::DoubleBuffer<std::uint64_t> kb(nullptr, nullptr);
        cub::DoubleBuffer<std::uint32_t> vb(nullptr, nullptr);
        SPH_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(nullptr, sort_temp, kb, vb, int(capacity)));
        const std::size_t reduce_temp = gpu::reduce_stats_temp_bytes(std::uint32_t(capacity));
        temp_bytes_ = std::max({sort_temp, reduce_temp, gpu::longest_list_temp_bytes(std::uint32_t(capacity))});
        const std::size_t need = capacity * bytes_per_particle + (std::size_t(ncells) + 1) * 8 + temp_bytes_ + (64 << 20);
        std::size_t free_b = 0, total_b = 0;
        SPH_CUDA_CHECK(cudaMemGetInfo(&free_b, &total_b));
        if (need > free_b) {
            char msg[320];
            std::snprintf(msg, sizeof msg,
                          "the scene needs %.2f GiB of GPU memory (%zu particles, %u cells) but %s (GPU %d) has "
                          "%.2f GiB free of %.2f GiB; use fewer particles",
                          need / 1073741824.0, capacity, ncells, name_.c_str(), device, free_b / 1073741824.0,
                          total_b / 1073741824.0);
            throw InputError(msg);
        }
        for (auto* b : {&pos_, &pos_alt_, &velrho_, &velrho_alt_, &velrho_prev_, &velrho_prev_alt_}) b->allocate(capacity);
        force_.allocate(capacity);
        if (cfg.params.shift > 0) grad_c_.allocate(capacity);
        cell_.allocate(capacity);
        id_.allocate(capacity);
        keys_.allocate(capacity);
        keys_alt_.allocate(capacity);
        order_.allocate(capacity);
        order_alt_.allocate(capacity);
        cell_start_.allocate(std::size_t(ncells) + 1);
        fluid_begin_.allocate(std::size_t(ncells) + 1);
        temp_.allocate(temp_bytes_);
        stats_.allocate(1);
        counters_.allocate(3);
        SPH_CUDA_CHECK(cudaMallocHost(reinterpret_cast<void**>(&host_stats_), sizeof(StepStats)));
        // The number of significant key bits: id in the low 32, then the cell (with its sentinel).
        int bits = 1;
        while ((std::uint64_t(1) << bits) <= ncells) ++bits;
        key_bits_ = 32 + bits;
        owned_[1] = ncells;
    }
    ~CudaSubdomain() override {
        cudaSetDevice(device_);  // unchecked: a destructor must not throw (the driver may be shutting down)
        cudaFreeHost(host_stats_);
        if (stream_) cudaStreamDestroy(stream_);
    }

    BackendKind backend() const override { return BackendKind::cuda; }
    std::string device_name() const override { return name_; }
    int device() const override { return device_; }
    void* stream() const override { return stream_; }

    void upload(const ParticleArrays& p) override {
        use_device();
        n_ = std::uint32_t(p.size());
        if (n_ > pos_.size()) throw RunError("more particles than the CUDA subdomain was sized for");
        pos_.upload(p.pos.data(), n_, stream_);
        velrho_.upload(p.velrho.data(), n_, stream_);
        velrho_prev_.upload(p.velrho_prev.empty() ? p.velrho.data() : p.velrho_prev.data(), n_, stream_);
        cell_.upload(p.cell.data(), n_, stream_);
        id_.upload(p.id.data(), n_, stream_);
        if (!p.force.empty()) force_.upload(p.force.data(), n_, stream_);
        else SPH_CUDA_CHECK(cudaMemsetAsync(force_.data(), 0, force_.bytes(), stream_));
        // Until the first sort every particle counts as active.
        const std::uint32_t ncells = cfg_.grid.cell_count();
        SPH_CUDA_CHECK(cudaMemsetAsync(cell_start_.data(), 0, cell_start_.bytes(), stream_));
        SPH_CUDA_CHECK(cudaMemsetAsync(fluid_begin_.data(), 0, fluid_begin_.bytes(), stream_));
        SPH_CUDA_CHECK(cudaMemcpyAsync(cell_start_.data() + ncells, &n_, sizeof n_, cudaMemcpyHostToDevice, stream_));
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        n_active_ = n_;
    }

    ParticleArrays download() override {
        use_device();
        ParticleArrays p;
        p.pos.resize(n_);
        p.velrho.resize(n_);
        p.velrho_prev.resize(n_);
        p.force.resize(n_);
        p.cell.resize(n_);
        p.id.resize(n_);
        pos_.download(p.pos.data(), n_, stream_);
        velrho_.download(p.velrho.data(), n_, stream_);
        velrho_prev_.download(p.velrho_prev.data(), n_, stream_);
        force_.download(p.force.data(), n_, stream_);
        cell_.download(p.cell.data(), n_, stream_);
        id_.download(p.id.data(), n_, stream_);
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        return p;
    }

    void set_owned_cells(std::uint32_t begin, std::uint32_t end) override {
        use_device();
        const std::uint32_t ncells = cfg_.grid.cell_count();
        owned_[0] = std::min(begin, ncells);
        owned_[1] = std::min(end, ncells);
        active_stale_ = true;
        gpu::mark_ghosts(cell_.data(), id_.data(), n_, begin, end, cfg_.grid.out_of_domain(), stream_);
    }
    void keep_only_cells(std::uint32_t begin, std::uint32_t end) override {
        use_device();
        const auto r = cell_starts({begin, end, cfg_.grid.cell_count()});
        const std::uint32_t lo = r[0], kept = r[1] - r[0], out_lo = r[2], out_n = n_ - r[2];
        if (lo == 0 && r[1] == out_lo) return;  // nothing to drop
        // Two ranges into the spare buffers, then swap: the ranges may overlap their targets.
        auto move = [&](auto& buf, auto& spare) {
            using T = std::decay_t<decltype(*buf.data())>;
            if (kept) SPH_CUDA_CHECK(cudaMemcpyAsync(spare.data(), buf.data() + lo, kept * sizeof(T), cudaMemcpyDeviceToDevice, stream_));
            if (out_n) SPH_CUDA_CHECK(cudaMemcpyAsync(spare.data() + kept, buf.data() + out_lo, out_n * sizeof(T), cudaMemcpyDeviceToDevice, stream_));
            buf.swap(spare);
        };
        move(pos_, pos_alt_);
        move(velrho_, velrho_alt_);
        move(velrho_prev_, velrho_prev_alt_);  // forces are recomputed before they are read
        // cell and id have no spare of their own: the sort's key buffers serve (8 bytes each).
        auto* cell_spare = reinterpret_cast<std::uint32_t*>(keys_alt_.data());
        auto* id_spare = cell_spare + pos_.size();
        if (kept) {
            SPH_CUDA_CHECK(cudaMemcpyAsync(cell_spare, cell_.data() + lo, kept * 4, cudaMemcpyDeviceToDevice, stream_));
            SPH_CUDA_CHECK(cudaMemcpyAsync(id_spare, id_.data() + lo, kept * 4, cudaMemcpyDeviceToDevice, stream_));
        }
        if (out_n) {
            SPH_CUDA_CHECK(cudaMemcpyAsync(cell_spare + kept, cell_.data() + out_lo, out_n * 4, cudaMemcpyDeviceToDevice, stream_));
            SPH_CUDA_CHECK(cudaMemcpyAsync(id_spare + kept, id_.data() + out_lo, out_n * 4, cudaMemcpyDeviceToDevice, stream_));
        }
        n_ = kept + out_n;
        // The cell ranges follow what was kept (shifted down by lo, the other cells empty), as
        // on the host: the balancer reads per-slice counts from them, and an exchange's
        // set_owned_cells the owned range.
        gpu::clamp_cell_starts(cell_start_.data(), fluid_begin_.data(), cfg_.grid.cell_count(), lo, r[1], stream_);
        if (n_) {
            SPH_CUDA_CHECK(cudaMemcpyAsync(cell_.data(), cell_spare, n_ * 4, cudaMemcpyDeviceToDevice, stream_));
            SPH_CUDA_CHECK(cudaMemcpyAsync(id_.data(), id_spare, n_ * 4, cudaMemcpyDeviceToDevice, stream_));
        }
        active_stale_ = true;
    }
    ParticleSpan particles(std::size_t first, std::size_t count) override {
        return {pos_.data() + first, velrho_.data() + first, velrho_prev_.data() + first, cell_.data() + first,
                id_.data() + first, count, device_, stream_};
    }
    // With cell offsets in the list entries the listed loop reads a neighbour's position from
    // the list frame (positions against the rebuild's cells), not pos: a ghost refresh copies
    // the owner's frame bit for bit (recomputing it could contract differently).
    ParticleSpan state(std::size_t first, std::size_t count) override {
        real4* frame = list_cell_offsets_ && build_frame_.size() >= n_ ? build_frame_.data() : pos_.data();
        return {frame + first, velrho_.data() + first, velrho_prev_.data() + first, cell_.data() + first, nullptr,
                count, device_, stream_};
    }
    // Plain entries: the listed loop reads a neighbour's cell as coordinates, which advance
    // keeps for owned particles only; a ghost's come from the cell its owner sent (exact).
    void ghosts_refreshed(std::size_t first, std::size_t count) override {
        if (list_cell_offsets_ || !keeps_cell_coords() || count == 0) return;
        use_device();
        gpu::fill_cell_coords(cell_.data() + first, pos_.data() + first, KeptCells{cell_coords_.data() + first, nullptr},
                              cfg_.grid, std::uint32_t(count), stream_);
    }
    ParticleSpan receive_area(std::size_t count) override {
        use_device();
        if (count > recv_id_.size()) {
            const std::size_t room = count + count / 2;
            recv_pos_.allocate(room);
            recv_velrho_.allocate(room);
            recv_velrho_prev_.allocate(room);
            recv_cell_.allocate(room);
            recv_id_.allocate(room);
        }
        received_ = count;
        return {recv_pos_.data(), recv_velrho_.data(), recv_velrho_prev_.data(), recv_cell_.data(), recv_id_.data(),
                count, device_, stream_};
    }
    void accept_received() override {
        use_device();
        const std::size_t m = received_;
        received_ = 0;
        if (n_ + m > pos_.size())
            throw RunError("subdomain on " + name_ + " would hold " + std::to_string(n_ + m) +
                           " particles, more than the " + std::to_string(pos_.size()) + " it was sized for");
        if (m == 0) return;
        // On this stream, which the transport has ordered after the incoming copies.
        auto copy = [&](auto* to, const auto* from) {
            SPH_CUDA_CHECK(cudaMemcpyAsync(to + n_, from, m * sizeof(*from), cudaMemcpyDeviceToDevice, stream_));
        };
        copy(pos_.data(), recv_pos_.data());
        copy(velrho_.data(), recv_velrho_.data());
        copy(velrho_prev_.data(), recv_velrho_prev_.data());
        copy(cell_.data(), recv_cell_.data());
        copy(id_.data(), recv_id_.data());
        n_ += std::uint32_t(m);
    }
    ReceivedCount accept_received_in(std::uint32_t begin, std::uint32_t end, std::uint32_t owned_begin,
                                     std::uint32_t owned_end) override {
        use_device();
        const std::size_t m = received_;
        received_ = 0;
        // At most m more; the exact count comes back from the device.
        if (n_ + m > pos_.size())
            throw RunError("subdomain on " + name_ + " would hold " + std::to_string(n_ + m) +
                           " particles, more than the " + std::to_string(pos_.size()) + " it was sized for");
        const ReceivedCount c = gpu::append_received_in(
            {recv_pos_.data(), recv_velrho_.data(), recv_velrho_prev_.data(), recv_cell_.data(), recv_id_.data()},
            std::uint32_t(m), {pos_.data(), velrho_.data(), velrho_prev_.data(), cell_.data(), id_.data()}, n_, begin,
            end, owned_begin, owned_end, stream_);
        n_ += std::uint32_t(c.kept);
        return c;
    }
    void synchronize() override {
        use_device();
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
    }
    std::vector<std::uint32_t> cell_starts(const std::vector<std::uint32_t>& cells) override {
        use_device();
        std::vector<std::uint32_t> out(cells.size());
        // Slice boundaries are evenly spaced: one strided copy instead of one copy per value.
        const bool even = cells.size() > 2 && std::adjacent_find(cells.begin() + 1, cells.end(), [&](auto a, auto b) {
                                                   return b - a != cells[1] - cells[0];
                                               }) == cells.end() && cells[1] > cells[0];
        if (even)
            SPH_CUDA_CHECK(cudaMemcpy2DAsync(out.data(), 4, cell_start_.data() + cells[0],
                                             std::size_t(cells[1] - cells[0]) * 4, 4, cells.size(),
                                             cudaMemcpyDeviceToHost, stream_));
        else
            for (std::size_t k = 0; k < cells.size(); ++k)
                SPH_CUDA_CHECK(cudaMemcpyAsync(&out[k], cell_start_.data() + cells[k], 4, cudaMemcpyDeviceToHost, stream_));
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        return out;
    }
    std::size_t size() const override { return n_; }

    void sort_by_cell() override {
        use_device();
        gpu::make_sort_keys(cell_.data(), id_.data(), keys_.data(), order_.data(), n_, stream_);
        cub::DoubleBuffer<std::uint64_t> kb(keys_.data(), keys_alt_.data());
        cub::DoubleBuffer<std::uint32_t> vb(order_.data(), order_alt_.data());
        std::size_t tb = temp_bytes_;
        SPH_CUDA_CHECK(cub::DeviceRadixSort::SortPairs(temp_.data(), tb, kb, vb, int(n_), 0, key_bits_, stream_));
        gpu::gather_sorted(kb.Current(), vb.Current(), {pos_.data(), velrho_.data(), velrho_prev_.data()},
                           {pos_alt_.data(), velrho_alt_.data(), velrho_prev_alt_.data()}, cell_.data(), id_.data(), n_,
                           stream_);
        pos_.swap(pos_alt_);
        velrho_.swap(velrho_alt_);
        velrho_prev_.swap(velrho_prev_alt_);
        gpu::build_cell_start(cell_.data(), n_, cfg_.grid.cell_count(), cell_start_.data(), stream_);
        gpu::build_fluid_begin(velrho_.data(), cell_.data(), cell_start_.data(), n_, cfg_.grid.cell_count(),
                               fluid_begin_.data(), stream_);
        active_stale_ = true;
    }

    void compute_forces() override {
        use_device();
        if (cfg_.params.shift > 0)
            gpu::concentration_gradient(cfg_, inputs(), grad_c_.data(), active_range(), n_, stream_);
        gpu::compute_forces(cfg_, inputs(), force_.data(), active_range(), n_, stream_);
    }
    void build_neighbour_list(real skin) override {
        use_device();
        const real reach = cfg_.params.support + skin;
        require_stencil_reach(cfg_, reach);
        const GridView& g = cfg_.grid;
        if (!fits_cell_coords(g))
            throw RunError("Verlet lists on the GPU take grids of at most " + std::to_string(cell_coords_limit) +
                           " cells along an axis; this one has " + std::to_string(g.nx) + " x " + std::to_string(g.ny) +
                           " x " + std::to_string(g.nz) + " (use a cell search: drop --verlet)");
        if (list_count_.size() < n_) list_count_.allocate(n_);
        // The listed loop reads every neighbour's cell as coordinates, or, with cell offsets in
        // its entries, positions against the rebuild's cells; advance keeps them from here on.
        list_cell_offsets_ = gpu::lists_take_cell_offsets(cfg_, n_);
        if (cell_coords_.size() < n_) cell_coords_.allocate(n_);
        if (list_cell_offsets_ && build_frame_.size() < n_) build_frame_.allocate(n_);
        gpu::fill_cell_coords(cell_.data(), pos_.data(), kept_cells(), g, n_, stream_);
        for (int attempt = 0; attempt < 2; ++attempt) {
            const std::size_t need = std::size_t(list_capacity_) * n_;
            if (list_index_.size() < need) {
                list_index_ = DeviceBuffer<std::uint32_t>();  // free first: the lists are the largest buffer
                list_index_.allocate(need);
            }
            gpu::build_neighbour_lists(cfg_, inputs(), reach * reach, list_index_.data(), list_count_.data(), n_,
                                       list_capacity_, list_cell_offsets_, active_range(), n_, stream_);
            const std::uint32_t longest =
                gpu::longest_list(list_count_.data(), n_, temp_.data(), temp_bytes_, counters32_.data(), stream_);
            if (longest <= list_capacity_) return;
            list_capacity_ = list_capacity(longest + longest / 5 + 8);  // grow with room, then build again
        }
    }
    void compute_forces_listed() override {
        use_device();
        const NeighbourList list{list_index_.data(), list_count_.data(), n_, list_cell_offsets_};
        gpu::compute_forces_listed(cfg_, inputs(), list, force_.data(), active_range(), n_, stream_);
    }
    std::size_t neighbour_list_bytes() const override {
        return list_index_.bytes() + list_count_.bytes() + cell_coords_.bytes() + build_frame_.bytes();
    }
    StoredLists download_neighbour_lists() override {
        use_device();
        std::vector<std::uint32_t> count(std::min<std::size_t>(list_count_.size(), n_)),
            index(std::min<std::size_t>(list_index_.size(), std::size_t(list_capacity_) * n_));
        SPH_CUDA_CHECK(cudaMemcpyAsync(count.data(), list_count_.data(), count.size() * 4, cudaMemcpyDeviceToHost, stream_));
        SPH_CUDA_CHECK(cudaMemcpyAsync(index.data(), list_index_.data(), index.size() * 4, cudaMemcpyDeviceToHost, stream_));
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        StoredLists out{{0}, {}};
        for (std::size_t i = 0; i < count.size(); ++i) {
            for (std::uint32_t k = 0; k < std::min(count[i], list_capacity_); ++k) {
                const std::uint32_t e = index[list_slot(k, std::uint32_t(i), n_)];
                out.index.push_back(list_cell_offsets_ ? ListEntry::index(e) : e);
            }
            out.first.push_back(std::uint32_t(out.index.size()));
        }
        return out;
    }

    void advance(const TimeStep& step) override {
        use_device();
        gpu::advance(pos_.data(), velrho_.data(), velrho_prev_.data(), cell_.data(),
                     kept_cells(), force_.data(),
                     grad_c_.size() ? grad_c_.data() : nullptr, step, cfg_, active_range(), n_, stream_);
    }

    void advance_cells(const TimeStep& step, std::uint32_t first_cell, std::uint32_t end_cell) override {
        use_device();
        const std::uint32_t f = std::clamp(first_cell, owned_[0], owned_[1]);
        const std::uint32_t e = std::clamp(end_cell, f, owned_[1]);
        if (e == f) return;
        gpu::advance(pos_.data(), velrho_.data(), velrho_prev_.data(), cell_.data(),
                     kept_cells(), force_.data(),
                     grad_c_.size() ? grad_c_.data() : nullptr, step, cfg_,
                     {cell_start_.data() + f, cell_start_.data() + e}, n_, stream_);
    }

    StepStats reduce_stats(const TimeStep& step, const StatsLimits& limits) override {
        use_device();
        gpu::reduce_stats(velrho_.data(), velrho_prev_.data(), force_.data(), id_.data(), active_range(), step,
                          cfg_.params, limits, n_, temp_.data(), temp_bytes_, stats_.data(), stream_);
        stats_.download(host_stats_, 1, stream_);
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        return *host_stats_;
    }

    WorkCounters count_work() override {
        use_device();
        gpu::count_work(cfg_, inputs(), active_range(), n_, counters_.data(), stream_);
        unsigned long long c[3];
        counters_.download(c, 3, stream_);
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        return {c[0], c[1], c[2]};
    }

    std::vector<GaugeSum> gauge_sums(const std::vector<GaugeProbe>& probes) override {
        use_device();
        if (probes.empty()) return {};
        if (gauge_probes_.size() < probes.size()) {
            gauge_probes_.allocate(probes.size());
            gauge_sums_.allocate(probes.size());
        }
        bool force = false;
        for (const GaugeProbe& p : probes) force = force || p.kind == GaugeKind::force;
        if (force && gauge_force_.size() < n_) gauge_force_.allocate(pos_.size());  // freed with the subdomain
        gauge_probes_.upload(probes.data(), probes.size(), stream_);
        const GaugeInputs in{inputs(), id_.data(), owned_[0], owned_[1]};
        gpu::gauge_sums(cfg_, in, gauge_probes_.data(), probes, n_, gauge_force_.data(), gauge_sums_.data(), stream_);
        std::vector<GaugeSum> out(probes.size());
        gauge_sums_.download(out.data(), out.size(), stream_);
        SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
        return out;
    }

    std::size_t active_count() const override {
        use_device();
        if (active_stale_) {
            std::uint32_t r[2];
            SPH_CUDA_CHECK(cudaMemcpyAsync(&r[0], cell_start_.data() + owned_[0], 4, cudaMemcpyDeviceToHost, stream_));
            SPH_CUDA_CHECK(cudaMemcpyAsync(&r[1], cell_start_.data() + owned_[1], 4, cudaMemcpyDeviceToHost, stream_));
            SPH_CUDA_CHECK(cudaStreamSynchronize(stream_));
            n_active_ = r[1] - r[0];
            active_stale_ = false;
        }
        return n_active_;
    }
    std::size_t bytes_allocated() const override {
        return pos_.size() * bytes_per_particle + cell_start_.bytes() + fluid_begin_.bytes() + temp_.bytes() +
               neighbour_list_bytes();
    }
    PhaseClock& clock() override { return clock_; }

private:
    ForceInputs inputs() const {
        const bool kept = keeps_cell_coords();
        return {pos_.data(), velrho_.data(), velrho_prev_.data(), cell_.data(), cell_start_.data(), fluid_begin_.data(),
                cfg_.grid, kept ? cell_coords_.data() : nullptr,
                kept && list_cell_offsets_ ? build_frame_.data() : nullptr};
    }
    // Kept once lists were built (Verlet lists), and from then on by every advance; empty before.
    bool keeps_cell_coords() const { return n_ > 0 && cell_coords_.size() >= n_; }
    KeptCells kept_cells() {
        if (!keeps_cell_coords()) return {};
        return {cell_coords_.data(), list_cell_offsets_ ? build_frame_.data() : nullptr};
    }
    gpu::ActiveRange active_range() const { return {cell_start_.data() + owned_[0], cell_start_.data() + owned_[1]}; }
    // Subdomains of one run live on different GPUs and share the host thread: every entry
    // point makes its GPU current first (cheap when it already is).
    void use_device() const { SPH_CUDA_CHECK(cudaSetDevice(device_)); }
    static cudaStream_t create_stream(int device) {
        SPH_CUDA_CHECK(cudaSetDevice(device));
        cudaStream_t s = nullptr;
        SPH_CUDA_CHECK(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking));
        return s;
    }

    SubdomainConfig cfg_;
    int device_;
    std::string name_;
    cudaStream_t stream_ = nullptr;
    CudaPhaseClock clock_;
    DeviceBuffer<real4> pos_, pos_alt_, velrho_, velrho_alt_, velrho_prev_, velrho_prev_alt_, force_;
    DeviceBuffer<real4> grad_c_;  // shifting only: written by compute_forces' gradient pass, read by advance
    DeviceBuffer<std::uint32_t> cell_, id_, order_, order_alt_, cell_start_, fluid_begin_;
    DeviceBuffer<std::uint64_t> keys_, keys_alt_;
    DeviceBuffer<unsigned char> temp_;
    DeviceBuffer<StepStats> stats_;
    DeviceBuffer<unsigned long long> counters_;
    DeviceBuffer<std::uint32_t> list_index_, list_count_, counters32_{1};
    DeviceBuffer<CellCoords> cell_coords_;
    DeviceBuffer<GaugeProbe> gauge_probes_;  // gauges: allocated on the first call
    DeviceBuffer<GaugeSum> gauge_sums_;
    DeviceBuffer<real4> gauge_force_;        // force gauges: each particle's force
    DeviceBuffer<real4> build_frame_;  // KeptCells::build_frame, while list_cell_offsets_
    bool list_cell_offsets_ = false;   // the lists' entries are ListEntry codes
    std::uint32_t list_capacity_ = 64;
    StepStats* host_stats_ = nullptr;
    DeviceBuffer<real4> recv_pos_, recv_velrho_, recv_velrho_prev_;  // the receive area of exchanges
    DeviceBuffer<std::uint32_t> recv_cell_, recv_id_;
    std::size_t received_ = 0;
    std::size_t temp_bytes_ = 0;
    int key_bits_ = 64;
    std::uint32_t n_ = 0;
    mutable std::uint32_t n_active_ = 0;
    std::uint32_t owned_[2] = {0, 0};
    mutable bool active_stale_ = false;
};

}  // namespace

std::unique_ptr<Subdomain> make_cuda_subdomain(const SubdomainConfig& cfg, std::size_t capacity, int device) {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess || count == 0)
        throw InputError("the CUDA backend was asked for, but no CUDA GPU is visible");
    if (device < 0 || device >= count)
        throw InputError("GPU " + std::to_string(device) + " does not exist: this machine has " +
                         std::to_string(count) + " GPU(s)");
    return std::make_unique<CudaSubdomain>(cfg, capacity, device);
}

int cuda_device_count() {
    int count = 0;
    return cudaGetDeviceCount(&count) == cudaSuccess ? count : 0;
}

bool cuda_backend_available() {
    int count = 0;
    return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

std::string cuda_device_summary() {
    int count = 0, driver = 0, runtime = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess) count = 0;
    cudaDriverGetVersion(&driver);
    cudaRuntimeGetVersion(&runtime);
    std::string s;
    for (int d = 0; d < count; ++d) {
        cudaDeviceProp prop{};
        if (cudaGetDeviceProperties(&prop, d) != cudaSuccess) continue;
        if (!s.empty()) s += "; ";
        s += prop.name;
    }
    return s + (s.empty() ? "" : " | ") + "driver " + std::to_string(driver / 1000) + "." +
           std::to_string(driver % 1000 / 10) + ", runtime " + std::to_string(runtime / 1000) + "." +
           std::to_string(runtime % 1000 / 10);
}

}  // namespace sph
