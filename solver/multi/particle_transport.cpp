#include "multi/particle_transport.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace sph {
namespace {

// Host subdomains share one address space: a transfer is one copy per array it carries.
class HostCopyTransport final : public ParticleTransport {
public:
    std::string name() const override { return "host"; }
    void deliver(std::vector<std::unique_ptr<Subdomain>>& subs, const std::vector<ParticleTransfer>& transfers,
                 const std::vector<ParticleSpan>& areas) override {
        for (const ParticleTransfer& t : transfers)
            for_each_array(areas[t.to], transfer_source(*subs[t.from], t),
                           [&](auto* dst, const auto* src) { std::copy_n(src, t.count, dst + t.offset); });
    }
};

}  // namespace

ParticleSpan source_arrays(Subdomain& sub, std::size_t first, std::size_t count, TransferArrays arrays) {
    return arrays == TransferArrays::state ? sub.state(first, count) : sub.particles(first, count);
}

TransportKind parse_transport(const std::string& text) {
    for (TransportKind k : {TransportKind::automatic, TransportKind::host, TransportKind::peer, TransportKind::staged,
                            TransportKind::nccl})
        if (text == transport_label(k)) return k;
    throw InputError("unknown transport '" + text + "': use auto, host, peer, staged or nccl");
}

const char* transport_label(TransportKind kind) {
    switch (kind) {
        case TransportKind::host: return "host";
        case TransportKind::peer: return "peer";
        case TransportKind::staged: return "staged";
        case TransportKind::nccl: return "nccl";
        default: return "auto";
    }
}

std::unique_ptr<ParticleTransport> make_transport(TransportKind kind,
                                                  const std::vector<std::unique_ptr<Subdomain>>& subs,
                                                  std::string& note) {
    const bool all_host = std::all_of(subs.begin(), subs.end(), [](auto& s) { return s->backend() == BackendKind::host; });
    const bool any_host = std::any_of(subs.begin(), subs.end(), [](auto& s) { return s->backend() == BackendKind::host; });
    if (all_host) {
        // A spec written for GPUs (a transport sweep) still runs on a machine without one.
        if (kind != TransportKind::automatic && kind != TransportKind::host)
            note = std::string(transport_label(kind)) +
                   " was asked for, but host subdomains share memory: particles are copied on the host";
        return std::make_unique<HostCopyTransport>();
    }
    if (any_host) throw InputError("a run mixes host and GPU subdomains, which no transport supports");
    if (kind == TransportKind::host)
        throw InputError("the host transport copies between host subdomains; GPU subdomains use peer, staged or nccl");
    return make_cuda_transport(kind, subs, note);
}

}  // namespace sph
