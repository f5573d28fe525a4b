// The GPU transports of particle_transport.hpp: peer copies, staging through host
// memory, and NCCL (nccl_library.cuh loads libnccl only when that transport is asked for).
#include <algorithm>
#include <set>
#include <utility>

#include "backend/cuda_check.cuh"
#include "backend/nccl_library.cuh"
#include "backend/pinned_staging.cuh"
#include "core/error.hpp"
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
    explicit PeerTransport(const std::vector<std::unique_ptr<Subdomain>>& subs) : events_(subs) {}
    std::string name() const override { return "peer"; }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        const auto pairs = pairs_of(transfers);
        // The source writes into the destination's receive area: wait until it is free.
        for (const auto& [from, to] : pairs) events_.order_after(to, stream_of(areas[to]), static_cast<cudaStream_t>(subs[from]->stream()));
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan src = subs[t.from]->particles(t.first, t.count);
            const ParticleSpan& dst = areas[t.to];
            SPH_CUDA_CHECK(cudaSetDevice(src.device));
            auto copy = [&](auto* to, const auto* from) {
                SPH_CUDA_CHECK(cudaMemcpyPeerAsync(to + t.offset, dst.device, from, src.device, t.count * sizeof(*from),
                                                   stream_of(src)));
            };
            copy(dst.pos, src.pos);
            copy(dst.velrho, src.velrho);
            copy(dst.velrho_prev, src.velrho_prev);
            copy(dst.cell, src.cell);
            copy(dst.id, src.id);
        }
        // The destination appends the received particles only after they have arrived.
        for (const auto& [from, to] : pairs) events_.order_after(from, static_cast<cudaStream_t>(subs[from]->stream()), stream_of(areas[to]));
    }

private:
    StreamEvents events_;
};

// Through page-locked host memory: for GPUs without peer access to each other.
class StagedTransport final : public ParticleTransport {
public:
    std::string name() const override { return "staged"; }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        std::size_t total = 0;
        for (const ParticleTransfer& t : transfers) total += t.count;
        if (total == 0) return;
        const PinnedStaging::Layout host = staging_.particles(total);
        std::size_t at = 0;
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan src = subs[t.from]->particles(t.first, t.count);
            SPH_CUDA_CHECK(cudaSetDevice(src.device));
            auto down = [&](auto* to, const auto* from) {
                SPH_CUDA_CHECK(cudaMemcpyAsync(to + at, from, t.count * sizeof(*from), cudaMemcpyDeviceToHost, stream_of(src)));
            };
            down(host.pos, src.pos);
            down(host.velrho, src.velrho);
            down(host.velrho_prev, src.velrho_prev);
            down(host.cell, src.cell);
            down(host.id, src.id);
            at += t.count;
        }
        for (auto& s : subs) s->synchronize();
        at = 0;
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan& dst = areas[t.to];
            SPH_CUDA_CHECK(cudaSetDevice(dst.device));
            auto up = [&](auto* to, const auto* from) {
                SPH_CUDA_CHECK(cudaMemcpyAsync(to + t.offset, from + at, t.count * sizeof(*from), cudaMemcpyHostToDevice,
                                               stream_of(dst)));
            };
            up(dst.pos, host.pos);
            up(dst.velrho, host.velrho);
            up(dst.velrho_prev, host.velrho_prev);
            up(dst.cell, host.cell);
            up(dst.id, host.id);
            at += t.count;
        }
        for (auto& s : subs) s->synchronize();  // the staging memory is reused next time
    }

private:
    PinnedStaging staging_;
};

// NCCL point-to-point: one rank per subdomain, every send and receive in one group, each on
// its subdomain's stream (so the ordering the interface promises comes from NCCL itself).
class NcclTransport final : public ParticleTransport {
public:
    explicit NcclTransport(const std::vector<std::unique_ptr<Subdomain>>& subs) {
        std::vector<int> devices;
        for (auto& s : subs) devices.push_back(s->device());
        if (std::set<int>(devices.begin(), devices.end()).size() != devices.size())
            throw InputError("the nccl transport needs one GPU per subdomain (NCCL has one rank per GPU); use "
                             "--transport peer when subdomains share a GPU");
        comms_ = NcclCommunicators(devices);
    }
    std::string name() const override { return "nccl"; }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        comms_.begin_group();
        for (const ParticleTransfer& t : transfers) {
            const ParticleSpan src = subs[t.from]->particles(t.first, t.count);
            const ParticleSpan& dst = areas[t.to];
            auto pass = [&](auto* to, const auto* from) {
                const std::size_t bytes = t.count * sizeof(*from);
                comms_.send(t.from, from, bytes, t.to, stream_of(src));
                comms_.receive(t.to, to + t.offset, bytes, t.from, stream_of(dst));
            };
            pass(dst.pos, src.pos);
            pass(dst.velrho, src.velrho);
            pass(dst.velrho_prev, src.velrho_prev);
            pass(dst.cell, src.cell);
            pass(dst.id, src.id);
        }
        comms_.end_group();  // a failure above leaves the group open; the run stops with it
    }

private:
    NcclCommunicators comms_;
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
    if (kind == TransportKind::staged) return std::make_unique<StagedTransport>();
    if (kind == TransportKind::nccl) return std::make_unique<NcclTransport>(subs);
    const auto [a, b] = missing_peer_access(devices);
    if (a >= 0) {
        const std::string why = "GPU " + std::to_string(a) + " has no peer access to GPU " + std::to_string(b);
        if (kind == TransportKind::peer) throw InputError("the peer transport cannot be used: " + why + "; use --transport staged");
        note = why + ": particles between GPUs are staged through host memory";
        return std::make_unique<StagedTransport>();
    }
    enable_peer_access(devices);
    return std::make_unique<PeerTransport>(subs);
}

}  // namespace sph
