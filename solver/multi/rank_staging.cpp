#include "multi/rank_staging.hpp"

#include "core/error.hpp"

namespace sph {
namespace {

// Host subdomains: the message is packed from, and unpacked into, their own memory.
class InPlaceStaging final : public RankStaging {
public:
    std::vector<ParticleSpan> stage_out(std::vector<std::unique_ptr<Subdomain>>& subs,
                                        const std::vector<StagedPiece>& pieces) override {
        std::vector<ParticleSpan> out;
        for (const StagedPiece& p : pieces) out.push_back(piece_source(*subs[p.sub], p));
        return out;
    }
    std::vector<ParticleSpan> stage_in(const std::vector<StagedPiece>& pieces,
                                       const std::vector<ParticleSpan>& areas) override {
        std::vector<ParticleSpan> in;
        for (const StagedPiece& p : pieces) in.push_back(sub_span(areas[p.sub], p.first, p.count));
        return in;
    }
    void deliver_in(std::vector<std::unique_ptr<Subdomain>>&, const std::vector<StagedPiece>&,
                    const std::vector<ParticleSpan>&) override {}
};

}  // namespace

const char* rank_transport_label(RankTransport kind) {
    switch (kind) {
        case RankTransport::host_memory: return "host-memory";
        case RankTransport::staged_pinned: return "staged-pinned";
        default: return "";
    }
}

RankTransportChoice choose_rank_transport(BackendKind backend, int ranks, bool gpu_direct, bool mpi_cuda_aware,
                                          const std::string& mpi_library) {
    if (gpu_direct && backend == BackendKind::host)
        throw InputError("GPU-direct (--gpu-direct, spec key gpu_direct) hands GPU memory to MPI, but this run uses the "
                         "host backend; drop --gpu-direct or run with --backend cuda");
    if (gpu_direct && ranks == 1)
        throw InputError("GPU-direct (--gpu-direct, spec key gpu_direct) concerns particles between MPI ranks, but "
                         "this run is one process; start it with mpirun or drop --gpu-direct");
    if (gpu_direct && !mpi_cuda_aware)
        throw InputError("GPU-direct (--gpu-direct, spec key gpu_direct) was asked for, but the MPI library (" +
                         mpi_library + ") has no CUDA support (MPIX_Query_cuda_support); drop --gpu-direct to "
                         "stage particles through pinned host memory, or use a CUDA-aware MPI");
    if (ranks == 1) return {};
    if (backend == BackendKind::host) return {RankTransport::host_memory, ""};
    RankTransportChoice c{RankTransport::staged_pinned, ""};
    if (gpu_direct)
        c.note = "GPU-direct was asked for and " + mpi_library +
                 " is CUDA-aware, but GPU memory is not handed to MPI yet: staged through pinned host memory";
    return c;
}

ParticleSpan sub_span(const ParticleSpan& s, std::size_t first, std::size_t count) {
    // A null array (one a transfer does not carry) stays null.
    auto at = [first](auto* p) { return p ? p + first : p; };
    return {at(s.pos), at(s.velrho), at(s.velrho_prev), at(s.cell), at(s.id), count, s.device, s.stream};
}

std::unique_ptr<RankStaging> make_rank_staging(RankTransport kind, const std::vector<std::unique_ptr<Subdomain>>& subs) {
    switch (kind) {
        case RankTransport::host_memory: return std::make_unique<InPlaceStaging>();
        case RankTransport::staged_pinned: return make_pinned_rank_staging(subs);
        default: return nullptr;
    }
}

}  // namespace sph
