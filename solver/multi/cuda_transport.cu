// The GPU transports of particle_transport.hpp: peer copies, staging through host
// memory, and NCCL (nccl_library.cuh loads libnccl only when that transport is asked for).
#include <algorithm>
#include <set>
#include <utility>

#include "backend/cuda_check.cuh"
#include "backend/nccl_library.cuh"
#include "backend/pinned_staging.cuh"
#include "core/error.hpp"
#include "multi/cuda_copy_streams.cuh"
#include "multi/particle_transport.hpp"

namespace sph {
namespace {

cudaStream_t stream_of(const ParticleSpan& s) { return static_cast<cudaStream_t>(s.stream); }

// One event per subdomain, created on its GPU, to order one stream after another's work.
class StreamEvents {
public:
    explicit StreamEvents(const std::vector<std::unique_ptr<Subdomain>>& subs) {
        for (auto& s : subs) {
            SPH_CUDA_CHECK(cudaSetDevice(s->device()));
            cudaEvent_t e = nullptr;
            SPH_CUDA_CHECK(cudaEventCreateWithFlags(&e, cudaEventDisableTiming));
            events_.push_back(e);
            devices_.push_back(s->device());
        }
    }
    ~StreamEvents() {
        for (std::size_t d = 0; d < events_.size(); ++d) {
            cudaSetDevice(devices_[d]);  // unchecked: destructors must not throw
            cudaEventDestroy(events_[d]);
        }
    }
    StreamEvents(const StreamEvents&) = delete;
    StreamEvents& operator=(const StreamEvents&) = delete;
    // Makes `waiter` wait for the work queued so far on subdomain d's stream.
    void order_after(int d, cudaStream_t stream_d, cudaStream_t waiter) {
        SPH_CUDA_CHECK(cudaSetDevice(devices_[d]));
        SPH_CUDA_CHECK(cudaEventRecord(events_[d], stream_d));
        SPH_CUDA_CHECK(cudaStreamWaitEvent(waiter, events_[d], 0));
    }

private:
    std::vector<cudaEvent_t> events_;
    std::vector<int> devices_;
};

// The pairs (source, destination) of an exchange, each once.
std::set<std::pair<int, int>> pairs_of(const std::vector<ParticleTransfer>& transfers) {
    std::set<std::pair<int, int>> p;
    for (const ParticleTransfer& t : transfers) p.insert({t.from, t.to});
    return p;
}

// GPU to GPU without the host: cudaMemcpyPeerAsync on the source's stream (over NVLink or
// PCIe with peer access; a local copy where both subdomains share a GPU).
class PeerTransport final : public ParticleTransport {
public:
    explicit PeerTransport(const std::vector<std::unique_ptr<Subdomain>>& subs) : events_(subs), lanes_(subs) {}
    std::string name() const override { return "peer"; }
    void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int d) override {
        lanes_.mark_ready(d, static_cast<cudaStream_t>(subs[d]->stream()));
    }
    // Each source copies on its own copy stream, after its boundary update and the
    // destination's (which comes after the destination last read its receive area).
    void begin_delivery(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                        const std::vector<ParticleSpan>& areas) override {
        pending_ = pairs_of(transfers);
        std::set<int> sources;
        for (const auto& [from, to] : pending_) {
            lanes_.copy_after_ready(from, to);
            if (sources.insert(from).second) lanes_.copy_after_ready(from, from);
        }
        for (int from : sources) lanes_.mark_start(from);
        for (const ParticleTransfer& t : transfers) copy_transfer(subs, t, areas[t.to], lanes_.copy(t.from));
        for (int from : sources) lanes_.mark_done(from);
    }
    void finish_delivery(std::vector<std::unique_ptr<Subdomain>>& subs) override {
        lanes_.finish(subs, pending_);
        pending_.clear();
    }
    double last_delivery_ms() override { return lanes_.elapsed_ms(); }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        const auto pairs = pairs_of(transfers);
        // The source writes into the destination's receive area: wait until it is free.
        for (const auto& [from, to] : pairs) events_.order_after(to, stream_of(areas[to]), static_cast<cudaStream_t>(subs[from]->stream()));
        for (const ParticleTransfer& t : transfers)
            copy_transfer(subs, t, areas[t.to], static_cast<cudaStream_t>(subs[t.from]->stream()));
        // The destination appends the received particles only after they have arrived.
        for (const auto& [from, to] : pairs) events_.order_after(from, static_cast<cudaStream_t>(subs[from]->stream()), stream_of(areas[to]));
    }

private:
    static void copy_transfer(std::vector<std::unique_ptr<Subdomain>>& subs, const ParticleTransfer& t,
                              const ParticleSpan& dst, cudaStream_t stream) {
        const ParticleSpan src = transfer_source(*subs[t.from], t);
        SPH_CUDA_CHECK(cudaSetDevice(src.device));
        for_each_array(carried_arrays(dst, t.arrays), src, [&](auto* to, const auto* from) {
            SPH_CUDA_CHECK(
                cudaMemcpyPeerAsync(to + t.offset, dst.device, from, src.device, t.count * sizeof(*from), stream));
        });
    }

    StreamEvents events_;
    CopyStreams lanes_;
    std::set<std::pair<int, int>> pending_;  // pairs of the delivery begun and not finished
};

// Through page-locked host memory: for GPUs without peer access to each other.
class StagedTransport final : public ParticleTransport {
public:
    explicit StagedTransport(const std::vector<std::unique_ptr<Subdomain>>& subs) : lanes_(subs) {}
    std::string name() const override { return "staged"; }
    void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int d) override {
        lanes_.mark_ready(d, static_cast<cudaStream_t>(subs[d]->stream()));
    }
    // On the copy streams, after the boundary updates: down, a host wait for the copy streams
    // only (the inner updates are already queued and go on), up, and a host wait again (the
    // staging memory is reused). Everything has arrived when this returns.
    void begin_delivery(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                        const std::vector<ParticleSpan>& areas) override {
        std::size_t total = 0;
        for (const ParticleTransfer& t : transfers) total += t.count;
        if (total == 0) return;
        std::set<int> involved;
        for (const ParticleTransfer& t : transfers) involved.insert({t.from, t.to});
        for (int d : involved) lanes_.copy_after_ready(d, d);
        const PinnedStaging::Layout host = staging_.particles(total);
        std::size_t at = 0;
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan src = transfer_source(*subs[t.from], t);
            SPH_CUDA_CHECK(cudaSetDevice(src.device));
            stage(t, src, host, at, true, lanes_.copy(t.from));
            at += t.count;
        }
        wait(involved);
        at = 0;
        for (const ParticleTransfer& t : transfers) {
            SPH_CUDA_CHECK(cudaSetDevice(areas[t.to].device));
            stage(t, areas[t.to], host, at, false, lanes_.copy(t.to));
            at += t.count;
        }
        wait(involved);
    }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        std::size_t total = 0;
        for (const ParticleTransfer& t : transfers) total += t.count;
        if (total == 0) return;
        const PinnedStaging::Layout host = staging_.particles(total);
        std::size_t at = 0;
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan src = transfer_source(*subs[t.from], t);
            SPH_CUDA_CHECK(cudaSetDevice(src.device));
            stage(t, src, host, at, true, stream_of(src));
            at += t.count;
        }
        for (auto& s : subs) s->synchronize();
        at = 0;
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan& dst = areas[t.to];
            SPH_CUDA_CHECK(cudaSetDevice(dst.device));
            stage(t, dst, host, at, false, stream_of(dst));
            at += t.count;
        }
        for (auto& s : subs) s->synchronize();  // the staging memory is reused next time
    }

private:
    // The arrays transfer `t` carries between device span `dev` (its source going down, its
    // destination's area coming up) and the staging memory at `at`.
    static void stage(const ParticleTransfer& t, const ParticleSpan& dev, const PinnedStaging::Layout& host,
                      std::size_t at, bool down, cudaStream_t stream) {
        for_each_array(carried_arrays(dev, t.arrays), staged_span(host, at, t.count), [&](auto* d, auto* h) {
            const std::size_t bytes = t.count * sizeof(*d);
            if (down) SPH_CUDA_CHECK(cudaMemcpyAsync(h, d, bytes, cudaMemcpyDeviceToHost, stream));
            else SPH_CUDA_CHECK(cudaMemcpyAsync(d + t.offset, h, bytes, cudaMemcpyHostToDevice, stream));
        });
    }
    void wait(const std::set<int>& lanes) {
        for (int d : lanes) SPH_CUDA_CHECK(cudaStreamSynchronize(lanes_.copy(d)));
    }

    PinnedStaging staging_;
    CopyStreams lanes_;
};

// NCCL point-to-point: one rank per subdomain, every send and receive in one group, each on
// its subdomain's stream (so the ordering the interface promises comes from NCCL itself).
class NcclTransport final : public ParticleTransport {
public:
    explicit NcclTransport(const std::vector<std::unique_ptr<Subdomain>>& subs) : lanes_(subs) {
        std::vector<int> devices;
        for (auto& s : subs) devices.push_back(s->device());
        if (std::set<int>(devices.begin(), devices.end()).size() != devices.size())
            throw InputError("the nccl transport needs one GPU per subdomain (NCCL has one rank per GPU); use "
                             "--transport peer when subdomains share a GPU");
        comms_ = NcclCommunicators(devices);
    }
    std::string name() const override { return "nccl"; }
    void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int d) override {
        lanes_.mark_ready(d, static_cast<cudaStream_t>(subs[d]->stream()));
    }
    // The same group of sends and receives, on the copy streams after the boundary updates.
    void begin_delivery(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                        const std::vector<ParticleSpan>& areas) override {
        pending_ = pairs_of(transfers);
        std::set<int> involved;
        for (const auto& [from, to] : pending_) involved.insert({from, to});
        for (int d : involved) lanes_.copy_after_ready(d, d);
        for (int d : involved) lanes_.mark_start(d);
        comms_.begin_group();
        for (const ParticleTransfer& t : transfers) pass(subs, t, areas[t.to], lanes_.copy(t.from), lanes_.copy(t.to));
        comms_.end_group();
        for (int d : involved) lanes_.mark_done(d);
        // finish: a source's later work waits for its copy stream; a destination's for its own
        // (which received), so order each after both.
        for (int d : involved) pending_.insert({d, d});
    }
    void finish_delivery(std::vector<std::unique_ptr<Subdomain>>& subs) override {
        lanes_.finish(subs, pending_);
        pending_.clear();
    }
    double last_delivery_ms() override { return lanes_.elapsed_ms(); }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        comms_.begin_group();
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan src = transfer_source(*subs[t.from], t);
            pass(subs, t, areas[t.to], stream_of(src), stream_of(areas[t.to]));
        }
        comms_.end_group();  // a failure above leaves the group open; the run stops with it
    }

private:
    void pass(std::vector<std::unique_ptr<Subdomain>>& subs, const ParticleTransfer& t, const ParticleSpan& dst,
              cudaStream_t send_stream, cudaStream_t receive_stream) {
        const ParticleSpan src = transfer_source(*subs[t.from], t);
        for_each_array(carried_arrays(dst, t.arrays), src, [&](auto* to, const auto* from) {
            const std::size_t bytes = t.count * sizeof(*from);
            comms_.send(t.from, from, bytes, t.to, send_stream);
            comms_.receive(t.to, to + t.offset, bytes, t.from, receive_stream);
        });
    }

    NcclCommunicators comms_;
    CopyStreams lanes_;
    std::set<std::pair<int, int>> pending_;
};

// Whether every two distinct GPUs of the run can reach each other; otherwise the first pair
// that cannot.
std::pair<int, int> missing_peer_access(const std::vector<int>& devices) {
    for (int a : devices)
        for (int b : devices) {
            if (a == b) continue;
            int ok = 0;
            SPH_CUDA_CHECK(cudaDeviceCanAccessPeer(&ok, a, b));
            if (!ok) return {a, b};
        }
    return {-1, -1};
}

void enable_peer_access(const std::vector<int>& devices) {
    for (int a : devices)
        for (int b : devices) {
            if (a == b) continue;
            SPH_CUDA_CHECK(cudaSetDevice(a));
            const cudaError_t e = cudaDeviceEnablePeerAccess(b, 0);
            if (e == cudaErrorPeerAccessAlreadyEnabled) cudaGetLastError();  // clears it: not an error
            else SPH_CUDA_CHECK(e);
        }
}

}  // namespace

std::unique_ptr<ParticleTransport> make_cuda_transport(TransportKind kind,
                                                       const std::vector<std::unique_ptr<Subdomain>>& subs,
                                                       std::string& note) {
    std::vector<int> devices;
    for (auto& s : subs) devices.push_back(s->device());
    std::sort(devices.begin(), devices.end());
    devices.erase(std::unique(devices.begin(), devices.end()), devices.end());
    if (kind == TransportKind::staged) return std::make_unique<StagedTransport>(subs);
    if (kind == TransportKind::nccl) return std::make_unique<NcclTransport>(subs);
    const auto [a, b] = missing_peer_access(devices);
    if (a >= 0) {
        const std::string why = "GPU " + std::to_string(a) + " has no peer access to GPU " + std::to_string(b);
        if (kind == TransportKind::peer) throw InputError("the peer transport cannot be used: " + why + "; use --transport staged");
        note = why + ": particles between GPUs are staged through host memory";
        return std::make_unique<StagedTransport>(subs);
    }
    enable_peer_access(devices);
    return std::make_unique<PeerTransport>(subs);
}

}  // namespace sph
