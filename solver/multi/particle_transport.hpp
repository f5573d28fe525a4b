#pragma once
// How particles travel between subdomains during an exchange. One interface, several ways:
//   host    copies between host subdomains (the host backend, and CI)
//   peer    GPU to GPU copies (cudaMemcpyPeerAsync over NVLink or PCIe; on one GPU a local copy)
//   staged  through page-locked host memory, for GPUs that cannot reach each other
//   nccl    NCCL send/receive, one rank per GPU (libnccl is loaded when asked for)
// These carry particles between the subdomains of one process (or MPI rank); between ranks,
// SlabExchange sends MPI messages, packed from host memory that a RankStaging provides
// (rank_staging.hpp: in place on the host, through pinned memory for GPU subdomains).
#include <memory>
#include <string>
#include <vector>

#include "backend/subdomain.hpp"

namespace sph {

// Which arrays a transfer carries: whole particles (an exchange: pos, velrho, velrho_prev,
// cell, id), or the state a neighbour's listed forces read of a ghost (a refresh between
// list rebuilds: all but id, which keeps the receiver's ghost flag; Subdomain::state).
enum class TransferArrays { whole, state };

// One transfer of an exchange: `count` particles of subdomain `from`, starting at its sorted
// particle `first`, land in the receive area of `to` at `offset`.
struct ParticleTransfer {
    int from = 0, to = 0;
    std::size_t first = 0, count = 0, offset = 0;
    TransferArrays arrays = TransferArrays::whole;
};

// The arrays of `arrays` of particles [first, first + count) of `sub`: its sorted particles
// whole, or their state (Subdomain::state).
ParticleSpan source_arrays(Subdomain& sub, std::size_t first, std::size_t count, TransferArrays arrays);
// The arrays of `transfer.arrays` of particles [first, first + count) of `sub`.
inline ParticleSpan transfer_source(Subdomain& sub, const ParticleTransfer& transfer) {
    return source_arrays(sub, transfer.first, transfer.count, transfer.arrays);
}
// `span` without the arrays that `arrays` does not carry (state: the ids).
inline ParticleSpan carried_arrays(ParticleSpan span, TransferArrays arrays) {
    if (arrays == TransferArrays::state) span.id = nullptr;
    return span;
}

// Calls f(dst_array, src_array) for each array the two spans both carry (a null array is not
// carried), in the order pos, velrho, velrho_prev, cell, id.
template <class F>
void for_each_array(const ParticleSpan& dst, const ParticleSpan& src, F&& f) {
    if (dst.pos && src.pos) f(dst.pos, src.pos);
    if (dst.velrho && src.velrho) f(dst.velrho, src.velrho);
    if (dst.velrho_prev && src.velrho_prev) f(dst.velrho_prev, src.velrho_prev);
    if (dst.cell && src.cell) f(dst.cell, src.cell);
    if (dst.id && src.id) f(dst.id, src.id);
}

class ParticleTransport {
public:
    virtual ~ParticleTransport() = default;
    virtual std::string name() const = 0;
    // Carries every transfer into the receive areas the caller has sized. Afterwards each
    // destination's queued work is ordered after its incoming data (a GPU copy may still be in
    // flight), and each source's queued work after its outgoing reads, so that both can go on
    // rearranging their arrays.
    virtual void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                         const std::vector<ParticleSpan>& receive_areas) = 0;

    // The exchange of paper section 5.3, which runs under the subdomains' inner update:
    // mark_ready(d) is called once subdomain d's boundary area is queued for update (what is
    // queued after it, the inner update, is not waited for); begin_delivery, once every
    // subdomain is marked, carries the transfers after the marks, on streams of the
    // transport's own where it has them, without holding the subdomains' streams back;
    // finish_delivery then orders each subdomain's later work after the delivery (no host
    // wait). Host copies have nothing to overlap with on one thread: they copy in
    // begin_delivery.
    virtual void mark_ready(std::vector<std::unique_ptr<Subdomain>>& subs, int d) {
        (void)subs;
        (void)d;
    }
    virtual void begin_delivery(std::vector<std::unique_ptr<Subdomain>>& subs,
                                const std::vector<ParticleTransfer>& transfers,
                                const std::vector<ParticleSpan>& receive_areas) {
        deliver(subs, transfers, receive_areas);
    }
    virtual void finish_delivery(std::vector<std::unique_ptr<Subdomain>>& subs) { (void)subs; }
    // How long the copies of the last delivery begun took where they ran (CUDA events on the
    // transport's streams: the longest stream, from its first copy to its last), waiting for
    // them; -1 where the host's wall time of begin_delivery covers them (host copies, staging).
    virtual double last_delivery_ms() { return -1; }
};

enum class TransportKind { automatic, host, peer, staged, nccl };

// "auto", "host", "peer", "staged" or "nccl"; throws InputError naming the allowed values.
TransportKind parse_transport(const std::string& text);
const char* transport_label(TransportKind kind);

// The transport for these subdomains. `automatic` picks host copies for host subdomains and
// peer copies between GPUs, falling back to staging through host memory (with a note saying
// so in `note`) where two GPUs have no peer access. Host subdomains always use host copies
// (with a note when another transport was asked for). Asking GPUs for a transport they
// cannot use is an InputError naming the reason.
std::unique_ptr<ParticleTransport> make_transport(TransportKind kind,
                                                  const std::vector<std::unique_ptr<Subdomain>>& subs,
                                                  std::string& note);

// The CUDA transports (cuda_transport.cu; without CUDA, a build without it says so).
std::unique_ptr<ParticleTransport> make_cuda_transport(TransportKind kind,
                                                       const std::vector<std::unique_ptr<Subdomain>>& subs,
                                                       std::string& note);

}  // namespace sph
